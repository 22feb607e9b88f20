// SPDX-License-Identifier: GPL-3.0-or-later
// The default (reduced, geometrically consistent) rod against the geometrically exact rod
// (rod.type = exact), run end to end through the run layer: the Simeon flexible slider-crank in
// its periodic steady state with 2 % damping (issue 23's acceptance: the peak midpoint
// deflection from the chord within 1 %), and the same for the rod's peak gauge stress. Before the
// reduced rod carried the geometric stiffness of its distributed axial force it read 1.80e-3 m
// against the exact 1.55e-3 m (16 % high).
#include <gtest/gtest.h>

#include <cmath>

#include "study/presets.h"
#include "study/run.h"

namespace flexrod {
namespace {

Config Preset(const std::string& name, const std::vector<std::string>& sets) {
  Config cfg;
  cfg.LoadToml(FindPreset(name)->toml, name);
  for (const std::string& s : sets) cfg.SetAssignment(s);
  return cfg;
}

struct Peaks {
  double deflection, stress;
};

Peaks SimeonPeaks(const std::string& rod_type, const std::string& rel_tol) {
  const Config cfg =
      Preset("simeon-crank", {"rod.type=" + rod_type, "sim.start=steady", "damping.type=ratio",
                              "damping.ratio=0.02", "sim.rel_tol=" + rel_tol});
  const RunResult r = RunSimulation(cfg, nullptr, false, RunOutputOptions{});
  EXPECT_TRUE(r.ok()) << r.status.Summary();
  EXPECT_TRUE(r.summary["steady_start"]["converged"].get<bool>());
  return {r.summary["channels"]["rod_deflection"]["peak_abs"].get<double>(),
          r.summary["rod"]["peak_gauge_stress [Pa]"].get<double>()};
}

// Measured at the preset's rel_tol 1e-7: reduced 1.5481e-3 m / 138.7 MPa, exact 1.5477e-3 m /
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

}  // namespace
}  // namespace flexrod
