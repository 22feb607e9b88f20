// tests/run/rigid_rig_reftest.cc — the rigid rig against the one load amplification the thesis
// measured: at 101 rpm with 1 mm clearance the peak slider acceleration is "almost 40 times" the
// ideal-joint prediction (thesis section 2.2.4, Fig. 26; RIG.md §1). The rigid-rig preset's guide
// (damping, Coulomb force) is calibrated to it (examples/rigid-rig.toml); this test keeps the
// preset, the hybrid law and the clearance joint on that number.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "input/presets.h"
#include "run/run.h"

namespace flexrod {
namespace {

double PeakMagnitude(const study::TimeSeries& ts) {
  double peak = 0.0;
  for (double a : ts.values("slider_acceleration")) peak = std::max(peak, std::abs(a));
  return peak;
}

TEST(RigidRigReference, PeakSliderAccelerationAt101RpmIsAboutFortyTimesTheIdealJoints) {
  Config cfg;
  cfg.LoadToml(FindPreset("rigid-rig")->toml, "rigid-rig");
  cfg.Set("drive.speed", "101 rpm");  // everything else as preset: 1 mm, hybrid law, μ = 0.18
  const RunResult run = RunSimulation(cfg);
  ASSERT_TRUE(run.ok()) << run.status.Summary();
  ASSERT_TRUE(run.ideal);
  const double real = PeakMagnitude(run.channels), ideal = PeakMagnitude(*run.ideal);
  // Ideal joint: r ω² (1 + r/ℓ) at the outer dead centre, 0.05 (101 π/30)² (1 + 1/6) = 6.526 m/s²
  // (the exact slider-crank peak; the twin's sampled peak sits within 1e-3 of it).
  EXPECT_NEAR(ideal, 0.05 * std::pow(101.0 * std::numbers::pi / 30.0, 2) * (1.0 + 0.05 / 0.3),
              1e-3 * ideal);
  // Thesis: "almost 40 times", read off one measured trace. Tolerance: a factor 1.6 either way.
  // The model's ratio is steep in the guide (17.6 … 124.6 for 18 … 21 N s/m, preset comment),
  // so the band checks the calibration holds, not a digit.
  const double ratio = real / ideal;
  std::printf(
      "rigid rig, 101 rpm, 1 mm: peak |a| %.1f m/s^2 real, %.3f m/s^2 ideal, ratio %.1f (thesis "
      "~40)\n",
      real, ideal, ratio);
  EXPECT_GT(ratio, 25.0);
  EXPECT_LT(ratio, 64.0);
}

}  // namespace
}  // namespace flexrod
