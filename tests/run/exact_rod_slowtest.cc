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

// The same for issue 23's second case: brass 12.7 mm, 0.5 mm, 250 rpm (impact bearing forces
// near 1.9 kN, above the rod's buckling load). This regime is sensitive to the trajectory: over
// the preset's 3 s (12.5 revolutions) the reduced rod's own peak bearing force read 1809 / 1778 /
// 1875 N at the default / 10x / 100x tighter tolerances (a round-off change of the Jacobian moved
// it 1.5 %), so, as issue 24 asks of such regimes, the statistics are taken over 5 s (20.8
// revolutions), where they read 1850 / 1875 / 1875 N. Measured against the exact rod (1890 N):
// p95 |a| −0.04 %, p95 bearing force −0.36 %, peak bearing force −2.1 %, peak gauge stress
// +0.28 % (reduced 339 275 steps, exact rod 404 019).
TEST(ExactRodReference, BrassRodAt250RpmReducedRodMatchesTheExactRod) {
  const std::vector<std::string> brass = {"rod.material=brass", "rod.height=12.7 mm",
                                          "drive.speed=250 rpm", "sim.capture=5 s"};
  const RigFigures reduced = FlexibleRig("flexible", brass);
  const RigFigures exact = FlexibleRig("exact", brass);
  EXPECT_NEAR(reduced.acc_p95, exact.acc_p95, 0.03 * exact.acc_p95);
  EXPECT_NEAR(reduced.force_p95, exact.force_p95, 0.03 * exact.force_p95);
  EXPECT_NEAR(reduced.force_peak, exact.force_peak, 0.03 * exact.force_peak);
  EXPECT_NEAR(reduced.stress_peak, exact.stress_peak, 0.03 * exact.stress_peak);
}

}  // namespace
}  // namespace flexrod
