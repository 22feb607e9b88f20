// SPDX-License-Identifier: GPL-3.0-or-later
// The default (reduced, geometrically consistent) rod against the geometrically exact rod
// (rod.type = exact), run end to end through the run layer: the Simeon flexible slider-crank in
// its periodic steady state with 2 % damping (issue 23's acceptance: the peak midpoint
// deflection from the chord within 1 %), and the same for the rod's peak gauge stress. Before the
// reduced rod carried the geometric stiffness of its distributed axial force it read 1.80e-3 m
// against the exact 1.55e-3 m (16 % high).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "input/presets.h"
#include "run/run.h"

namespace flexrod {
namespace {

struct Peaks {
  double deflection, stress;
};

Peaks SimeonPeaks(const std::string& rod_type, const std::string& rel_tol) {
  const Config cfg = LoadRunInput(
      "simeon-crank", {"rod.type=" + rod_type, "sim.start=steady", "damping.type=ratio",
                       "damping.ratio=0.02", "sim.rel_tol=" + rel_tol,
                       "sim.abs_tol=1e-10"});  // damped: 1e-10 suffices (the preset: 1e-11)
  const RunResult r = RunSimulation(cfg, nullptr, false, RunOutputOptions{});
  EXPECT_TRUE(r.ok()) << r.status.Summary();
  EXPECT_TRUE(r.summary["steady_start"]["converged"].get<bool>());
  return {r.summary["channels"]["rod_deflection"]["peak_abs"].get<double>(),
          r.summary["rod"]["peak_gauge_stress [Pa]"].get<double>()};
}

// Measured at rel_tol 1e-7, abs_tol 1e-10: reduced 1.5481e-3 m / 138.7 MPa, exact 1.5477e-3 m /
// 138.5 MPa (20 s for the exact rod, 40 elements, 145 unknowns).
TEST(ExactRodReference, SimeonCrankReducedRodMatchesTheExactRod) {
  const Peaks reduced = SimeonPeaks("flexible", "1e-7");
  const Peaks exact = SimeonPeaks("exact", "1e-7");
  EXPECT_NEAR(reduced.deflection, exact.deflection, 1e-2 * exact.deflection);
  EXPECT_NEAR(reduced.stress, exact.stress, 1e-2 * exact.stress);
  // The physical value (both models): well below the linear tangent-frame rod's 1.80e-3 m.
  EXPECT_NEAR(exact.deflection, 1.548e-3, 5e-3 * 1.548e-3);
  ::testing::Test::RecordProperty("reduced_deflection_m", std::to_string(reduced.deflection));
  ::testing::Test::RecordProperty("exact_deflection_m", std::to_string(exact.deflection));
}

struct RigFigures {
  double acc_p95, force_p95, force_peak, stress_peak;
};

RigFigures FlexibleRig(const std::string& rod_type, std::vector<std::string> sets = {}) {
  sets.insert(sets.end(), {"rod.type=" + rod_type, "damping.type=rayleigh", "damping.beta=2e-5"});
  const Config cfg = LoadRunInput("flexible-rig", sets);
  const RunResult r = RunSimulation(cfg, nullptr, false, RunOutputOptions{});
  EXPECT_TRUE(r.ok()) << r.status.Summary();
  const nlohmann::json& s = r.summary;
  std::printf(
      "%s: p95 per-revolution peak |a| %.6g, bearing force p95 amplification %.6g, "
      "peak %.6g N, peak gauge stress %.6g Pa\n",
      rod_type.c_str(), s["slider_acceleration"]["per_revolution_abs"]["p95"].get<double>(),
      s["load_amplification"]["bearing_force_p95"].get<double>(),
      s["load_amplification"]["bearing_force_peak_real [N]"].get<double>(),
      s["rod"]["peak_gauge_stress [Pa]"].get<double>());
  return {s["slider_acceleration"]["per_revolution_abs"]["p95"].get<double>(),
          s["load_amplification"]["bearing_force_p95"].get<double>(),
          s["load_amplification"]["bearing_force_peak_real [N]"].get<double>(),
          s["rod"]["peak_gauge_stress [Pa]"].get<double>()};
}

// Issue 23's acceptance on the flexible rig with its clearance joint (the main job: steel 12.7
// mm, 0.5 mm, 200 rpm, 3 s capture = 10 revolutions), the same Rayleigh β = 2e-5 s on both rods
// (Kelvin–Voigt on the strains): the default reduced rod (Craig–Bampton 8, second-order strain,
// small-end clamp a welded body) within 3 % of the exact rod on the p95 of the per-revolution
// peak slider acceleration and of the bearing force (amplification), the peak bearing force and
// the peak gauge stress. Measured: +0.33 %, +0.45 %, +0.36 %, +0.13 %.
// Before: −8.4 % with the bush offset turning linearly with the node, +32 % with linear axial
// strain (no chord shortening).
TEST(ExactRodReference, FlexibleRigReducedRodMatchesTheExactRod) {
  const RigFigures reduced = FlexibleRig("flexible");
  const RigFigures exact = FlexibleRig("exact");
  EXPECT_NEAR(reduced.acc_p95, exact.acc_p95, 0.03 * exact.acc_p95);
  EXPECT_NEAR(reduced.force_p95, exact.force_p95, 0.03 * exact.force_p95);
  EXPECT_NEAR(reduced.force_peak, exact.force_peak, 0.03 * exact.force_peak);
  EXPECT_NEAR(reduced.stress_peak, exact.stress_peak, 0.03 * exact.stress_peak);
}

// The default band damping on both rods (the main job, one member; the figures the README
// quotes). Both realise the band's ratios on the mechanism's modes (the exact rod exactly up to
// the first critical mode, tests/mechanisms/mechanism_damping_reftest.cc), yet they differ: the
// modal ratios of the constrained mechanism do not fix the damping of a small end flying free in
// its clearance, and the reduced rod has no modes above its basis (mechanisms/mechanism_damping.h
// has the measurements). This holds the README's figures to 1 % and the gap to what it is:
// the exact rod above the reduced rod on all three (measured +3.5 %, +11.7 %, +6.6 %), so that
// a change that closes or opens it is seen. Issue 57's 2 % is not met.
TEST(ExactRodReference, MainJobWithBandDampingOnBothRods) {
  auto figures = [](const std::string& rod_type) {
    const Config cfg = LoadRunInput("flexible-rig", {"rod.type=" + rod_type, "ensemble.members=1"});
    const RunResult r = RunSimulation(cfg, nullptr, false, RunOutputOptions{});
    EXPECT_TRUE(r.ok()) << r.status.Summary();
    const nlohmann::json& a = r.summary["load_amplification"];
    return std::vector<double>{a["slider_acceleration_positive"].get<double>(),
                               a["slider_acceleration_negative"].get<double>(),
                               a["bearing_force"].get<double>()};
  };
  const std::vector<double> reduced = figures("flexible"), exact = figures("exact");
  const std::vector<double> readme_reduced = {7.67, 6.00, 7.63}, readme_exact = {7.94, 6.70, 8.13};
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(reduced[k], readme_reduced[k], 0.01 * readme_reduced[k]) << k;
    EXPECT_NEAR(exact[k], readme_exact[k], 0.01 * readme_exact[k]) << k;
    static const char* const kNames[] = {
        "exact_over_reduced_positive", "exact_over_reduced_negative", "exact_over_reduced_bearing"};
    ::testing::Test::RecordProperty(kNames[k], std::to_string(exact[k] / reduced[k]));
  }
}

// The same for issue 23's second case: brass 12.7 mm, 0.5 mm, 250 rpm (impact bearing forces
// near 1.9 kN, above the rod's buckling load), over 5 s (20.8 revolutions). This regime is
// chaotic: a round-off-level change moves a run's figures by up to 3 %, as much as the bound.
// Measured here, each model at sim.rel_tol 1e-6, 1.00001e-6 and 0.99999e-6:
//   p95 |a| [m/s²]            reduced 593.96 595.42 594.64   exact 593.95 595.24 594.17
//   p95 bearing-force ampl.   reduced 25.958 26.094 26.152   exact 26.493 25.878 26.197
//   peak bearing force [N]    reduced 1829   1837   1840     exact 1869   1833   1839
//   peak gauge stress [MPa]   reduced 55.82  56.40  56.08    exact 56.00  56.26  54.82
// (a change of the mass-matrix product's rounding once moved the reduced rod's single run to
// 3.7 % and 4.1 % off the exact rod's, on the p95 and peak bearing force). So, as issue 24 asks
// of chaotic regimes, the figures compared are means over those three neighbouring trajectories
// of each model: measured +0.04 %, −0.46 %, −0.64 %, +0.73 %.
RigFigures NeighbourMean(const std::string& rod_type, const std::vector<std::string>& sets) {
  RigFigures mean{0.0, 0.0, 0.0, 0.0};
  const std::vector<std::string> tolerances = {"1e-6", "1.00001e-6", "0.99999e-6"};
  for (const std::string& rel_tol : tolerances) {
    std::vector<std::string> run_sets = sets;
    run_sets.push_back("sim.rel_tol=" + rel_tol);
    const RigFigures f = FlexibleRig(rod_type, run_sets);
    mean.acc_p95 += f.acc_p95 / static_cast<double>(tolerances.size());
    mean.force_p95 += f.force_p95 / static_cast<double>(tolerances.size());
    mean.force_peak += f.force_peak / static_cast<double>(tolerances.size());
    mean.stress_peak += f.stress_peak / static_cast<double>(tolerances.size());
  }
  return mean;
}

TEST(ExactRodReference, BrassRodAt250RpmReducedRodMatchesTheExactRod) {
  const std::vector<std::string> brass = {"rod.material=brass", "rod.height=12.7 mm",
                                          "drive.speed=250 rpm", "sim.capture=5 s"};
  const RigFigures reduced = NeighbourMean("flexible", brass);
  const RigFigures exact = NeighbourMean("exact", brass);
  std::printf(
      "means: reduced / exact - 1: p95 |a| %+.2f %%, p95 bearing force %+.2f %%, peak %+.2f %%, "
      "peak gauge stress %+.2f %%\n",
      100.0 * (reduced.acc_p95 / exact.acc_p95 - 1.0),
      100.0 * (reduced.force_p95 / exact.force_p95 - 1.0),
      100.0 * (reduced.force_peak / exact.force_peak - 1.0),
      100.0 * (reduced.stress_peak / exact.stress_peak - 1.0));
  EXPECT_NEAR(reduced.acc_p95, exact.acc_p95, 0.03 * exact.acc_p95);
  EXPECT_NEAR(reduced.force_p95, exact.force_p95, 0.03 * exact.force_p95);
  EXPECT_NEAR(reduced.force_peak, exact.force_peak, 0.03 * exact.force_peak);
  EXPECT_NEAR(reduced.stress_peak, exact.stress_peak, 0.03 * exact.stress_peak);
}

}  // namespace
}  // namespace flexrod
