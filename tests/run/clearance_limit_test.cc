// tests/run/clearance_limit_test.cc — a clearance joint whose clearance vanishes approaches
// the ideal revolute joint. The rigid rig (RIG.md §1, preset rigid-rig, 177 rpm) is run with a
// frictionless clearance joint (the ideal joint is frictionless) and a dissipative flores
// contact (cₑ = 0.3) whose stiffness is derived from the geometry (K ∝ √R*, so the contact
// stiffens as the clearance shrinks), and compared sample by sample with its ideal-joint twin
// over one revolution after settling (RunSimulation runs both on the same capture window).
// Measured (rel./abs. tolerance 1e-8/1e-10, converged: 1e-9/1e-12 agrees to 1e-3): the RMS
// difference of the slider acceleration over the revolution relative to the ideal RMS falls
// from 0.33 at c = 10 µm to 0.039 at c = 1 µm, the largest difference from 1.57 to 0.185 of the
// ideal peak (the residual spikes are the pin crossing the 2 µm gap at the force reversals). The
// test asserts < 0.06 at 1 µm (a few %), a fivefold drop from 10 µm, a smaller largest
// difference, and a contact penetration below the clearance.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "input/presets.h"
#include "run/run.h"

namespace flexrod {
namespace {

struct LimitResult {
  double rms_rel{0.0};  // RMS(a − a_ideal) / RMS(a_ideal) over the capture
  double max_rel{0.0};  // max|a − a_ideal| / max|a_ideal|
  double max_penetration{0.0};
  bool ok{false};
};

LimitResult RunLimit(const std::string& clearance) {
  Config cfg;
  cfg.LoadToml(FindPreset("rigid-rig")->toml, "rigid-rig");
  cfg.Set("joint.type", "clearance");
  cfg.Set("joint.clearance", clearance);
  cfg.Set("joint.law", "flores");
  cfg.Set("joint.restitution", "0.3");
  cfg.Set("joint.friction_law", "none");
  cfg.Set("sim.settle", "0.4 s");
  cfg.Set("sim.capture", "0.339 s");  // one revolution at 177 rpm
  // Tolerances well below the clearance: with the defaults (abs. 1e-8 m = 1 % of a 1 µm
  // clearance) the 1 µm result is not converged (RMS diff 0.145 measured, vs 0.039 at both
  // 1e-8/1e-10 and 1e-9/1e-12).
  cfg.Set("sim.rel_tol", "1e-8");
  cfg.Set("sim.abs_tol", "1e-10");
  const RunResult run = RunSimulation(cfg);
  LimitResult r;
  r.ok = run.ok() && run.ideal != nullptr;
  EXPECT_TRUE(run.ok()) << run.status.Summary();
  if (!r.ok) return r;
  const auto a = run.channels.values("slider_acceleration");
  const auto b = run.ideal->values("slider_acceleration");
  EXPECT_EQ(a.size(), b.size());
  double se = 0.0, si = 0.0, me = 0.0, mi = 0.0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    se += (a[i] - b[i]) * (a[i] - b[i]);
    si += b[i] * b[i];
    me = std::max(me, std::abs(a[i] - b[i]));
    mi = std::max(mi, std::abs(b[i]));
  }
  r.rms_rel = std::sqrt(se / si);
  r.max_rel = me / mi;
  for (double d : run.channels.values("penetration"))
    r.max_penetration = std::max(r.max_penetration, d);
  std::printf(
      "clearance %s: slider acceleration vs ideal: RMS diff %.4f, max diff %.4f of peak; "
      "max penetration %.3g m\n",
      clearance.c_str(), r.rms_rel, r.max_rel, r.max_penetration);
  return r;
}

TEST(ClearanceLimit, VanishingClearanceApproachesTheIdealMechanism) {
  const LimitResult coarse = RunLimit("0.01 mm");
  const LimitResult fine = RunLimit("0.001 mm");
  ASSERT_TRUE(coarse.ok && fine.ok);
  EXPECT_LT(fine.rms_rel, 0.06);
  EXPECT_LT(fine.rms_rel, 0.2 * coarse.rms_rel);
  EXPECT_LT(fine.max_rel, coarse.max_rel);
  EXPECT_LT(fine.max_penetration, 1e-6);
  ::testing::Test::RecordProperty("rms_rel_1um", std::to_string(fine.rms_rel));
  ::testing::Test::RecordProperty("rms_rel_10um", std::to_string(coarse.rms_rel));
}

}  // namespace
}  // namespace flexrod
