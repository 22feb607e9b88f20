// SPDX-License-Identifier: GPL-3.0-or-later
// The four-bar recipe (mechanisms/recipe_four_bar.cc) against the closed-form kinematics of a
// four-bar, from Freudenstein's equation (F. Freudenstein, "Approximate synthesis of four-bar
// linkages", Trans. ASME 77, 1955): with the ground link d along x, crank r, coupler l and
// rocker c, K1 cos φ − K2 cos θ + K3 = cos(θ − φ), K1 = d/r, K2 = d/c,
// K3 = (r² − l² + c² + d²)/(2 r c), solved for the rocker angle φ by the tangent half-angle.
// The recipe places the mechanism by intersecting two circles instead.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/error.h"
#include "input/presets.h"
#include "run/run.h"

namespace flexrod {
namespace {

struct Freudenstein {
  double r, l, c, d;
  /// The rocker angle φ [rad] at crank angle θ [rad], on the branch `sign` (±1).
  double phi(double th, double sign) const {
    const double k1 = d / r, k2 = d / c, k3 = (r * r - l * l + c * c + d * d) / (2 * r * c);
    const double A = std::cos(th) - k1 - k2 * std::cos(th) + k3;
    const double B = -2.0 * std::sin(th);
    const double C = k1 - (k2 + 1.0) * std::cos(th) + k3;
    return 2.0 * std::atan2(-B + sign * std::sqrt(B * B - 4 * A * C), 2 * A);
  }
};

Config FourBarRig(const std::vector<std::string>& sets) {
  Config cfg;
  cfg.LoadToml(FindPreset("rigid-rig")->toml, "rigid-rig");
  for (const char* s :
       {"mechanism.type=four-bar", "joint.type=ideal", "rod.big_end_x=0", "rod.big_end_y=0",
        "rod.small_end_x=0", "rod.small_end_y=0", "rocker.length=150 mm", "rocker.pivot_x=250 mm",
        "rocker.pivot_y=0", "sim.settle=0 s", "sim.capture=0.35 s", "sim.sample_rate=20 kHz",
        "sim.rel_tol=1e-10", "sim.abs_tol=1e-12"})
    cfg.SetAssignment(s);
  for (const std::string& s : sets) cfg.SetAssignment(s);
  return cfg;
}

double Wrap(double a) { return std::remainder(a, 2.0 * std::numbers::pi); }

TEST(FourBar, RigidRodFollowsFreudensteinsKinematics) {
  const Config cfg = FourBarRig({"rod.type=rigid"});
  const RunResult r = RunSimulation(cfg);
  ASSERT_TRUE(r.ok()) << r.status.Summary();
  const Freudenstein k{cfg.Quantity("crank.length"), cfg.Quantity("rod.length"), 0.15, 0.25};
  const double w = cfg.Quantity("drive.speed");
  const auto th = r.channels.values("crank_angle");
  const auto phi = r.channels.values("rocker_angle");
  const auto dphi = r.channels.values("rocker_angular_velocity");
  // The branch the run is on: the root nearer its first sample.
  const double sign =
      std::abs(Wrap(k.phi(th[0], 1.0) - phi[0])) < std::abs(Wrap(k.phi(th[0], -1.0) - phi[0]))
          ? 1.0
          : -1.0;
  double angle_err = 0.0, rate_err = 0.0, rate_scale = 0.0;
  constexpr double h = 1e-3;  // 5-point stencil in θ: truncation ~h⁴
  for (size_t i = 0; i < th.size(); i += 7) {
    angle_err = std::max(angle_err, std::abs(Wrap(phi[i] - k.phi(th[i], sign))));
    const double dphi_dth = (-k.phi(th[i] + 2 * h, sign) + 8 * k.phi(th[i] + h, sign) -
                             8 * k.phi(th[i] - h, sign) + k.phi(th[i] - 2 * h, sign)) /
                            (12 * h);
    rate_err = std::max(rate_err, std::abs(dphi[i] - w * dphi_dth));
    rate_scale = std::max(rate_scale, std::abs(w * dphi_dth));
  }
  EXPECT_GT(th.back() - th.front(), 2.0 * std::numbers::pi);  // more than a revolution
  EXPECT_LT(angle_err, 1e-8);
  EXPECT_LT(rate_err / rate_scale, 1e-6);
}

TEST(FourBar, ACrankThatCannotTurnFullyIsRefusedNamingTheRocker) {
  try {
    (void)RunSimulation(FourBarRig({"rocker.length=40 mm"}));
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "rocker.length");
  }
}

TEST(FourBar, AClearanceJointIsRefused) {
  try {
    (void)RunSimulation(FourBarRig({"joint.type=clearance"}));
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "joint.type");
  }
}

}  // namespace
}  // namespace flexrod
