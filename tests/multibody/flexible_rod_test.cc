// tests/multibody/flexible_rod_test.cc — the multibody engine with real reduced rods from
// fem::Reduce (Craig–Bampton): a rod 10⁴ times stiffer reproduces the rigid slider-crank; the
// sparse (KLU) and dense linear solvers give the same trajectory; the static-equilibrium
// start of a cantilever under gravity deflects its tip by q L⁴ / (8 E I) and does not move.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <numbers>

#include "mb_test_util.h"
#include "multibody/simulate.h"

namespace flexrod::multibody {
namespace {

using testing::BuildFlexibleSliderCrank;
using testing::MakeSteelRod;
using testing::SliderCrankExact;
using testing::SliderCrankGuess;
using testing::SliderCrankParams;

// Constant crank speed fixes the kinematics of a rigid mechanism; a 10⁴× stiffer rod deflects
// ~10⁴× less, so the slider follows the exact rigid formulas (mb_test_util.h). The rod starts
// undeformed: at t = 0 it cannot transmit the inertial load yet, and the resulting ringing of
// its modes (13 kHz – 2.5 MHz, critically damped by the band default) dies out within a
// millisecond, so the comparison starts at 2 ms. Tolerances: position 1e-7, velocity 1e-6,
// acceleration 1e-4 relative to the largest value over the revolution.
TEST(FlexibleRod, VeryStiffRodReproducesTheRigidSliderCrank) {
  SliderCrankParams P;
  P.e = 0.01;
  auto rod = MakeSteelRod(P.l, 10, 4, 1e4);
  auto sc = BuildFlexibleSliderCrank(P, rod);
  RunData data(sc.model);
  SimulationOptions opt;
  opt.t_end = 2.0 * std::numbers::pi / P.omega;
  opt.sample_rate = 2000.0;
  opt.integrator.rel_tol = 1e-8;
  opt.integrator.abs_tol = 1e-10;
  // Modes up to 2.5 MHz: the automatic velocity scale (1e4) lands in IDA's stiff error-
  // estimate trap for this extreme rod; 1e3 does not (see kElasticJointVelocityTolScale).
  opt.velocity_tol_scale = 1e3;
  const SliderCrankExact ex{P.r, P.l, P.e, P.omega};
  const int ix = sc.model.coordinate(sc.slider, kX);
  double ex_x = 0, ex_xd = 0, ex_xdd = 0, rx = 0, rxd = 0, rxdd = 0;
  SimulationCallbacks cb;
  cb.on_sample = [&](const SampleView& s) {
    if (s.t() < 2e-3) return;
    const double th = P.theta0 + P.omega * s.t();
    ex_x = std::max(ex_x, std::abs(s.coordinate(ix) - ex.x(th)));
    ex_xd = std::max(ex_xd, std::abs(s.velocity(ix) - ex.xd(th)));
    ex_xdd = std::max(ex_xdd, std::abs(s.acceleration(ix) - ex.xdd(th)));
    rx = std::max(rx, std::abs(ex.x(th)));
    rxd = std::max(rxd, std::abs(ex.xd(th)));
    rxdd = std::max(rxdd, std::abs(ex.xdd(th)));
  };
  const SimulationStatus st = Simulate(sc.model, &data, SliderCrankGuess(sc, P), opt, cb);
  ASSERT_TRUE(st.ok()) << st.Summary();
  EXPECT_LE(ex_x / rx, 1e-7);
  EXPECT_LE(ex_xd / rxd, 1e-6);
  EXPECT_LE(ex_xdd / rxdd, 1e-4);
  testing::Record("rel_err_x", ex_x / rx);
  testing::Record("rel_err_xd", ex_xd / rxd);
  testing::Record("rel_err_xdd", ex_xdd / rxdd);
  testing::Record("steps", static_cast<double>(st.stats.steps));
}

// Same model, same tolerances: the two linear solvers agree to the integration tolerance.
TEST(FlexibleRod, KluAndDenseSolversGiveTheSameTrajectory) {
  SliderCrankParams P;
  auto rod = MakeSteelRod(P.l, 10, 4);
  auto sc = BuildFlexibleSliderCrank(P, rod);
  const int ix = sc.model.coordinate(sc.slider, kX);
  auto run = [&](LinearSolverKind kind, std::vector<double>* x) {
    RunData data(sc.model);
    SimulationOptions opt;
    opt.t_end = 0.05;
    opt.sample_rate = 5000.0;
    opt.integrator.rel_tol = 1e-9;
    opt.integrator.abs_tol = 1e-11;
    opt.integrator.linear_solver = kind;
    SimulationCallbacks cb;
    cb.on_sample = [&](const SampleView& s) { x->push_back(s.coordinate(ix)); };
    const SimulationStatus st = Simulate(sc.model, &data, SliderCrankGuess(sc, P), opt, cb);
    EXPECT_TRUE(st.ok()) << st.Summary();
    EXPECT_EQ(st.linear_solver, kind);
    return st;
  };
  std::vector<double> xd, xk;
  run(LinearSolverKind::kDense, &xd);
  run(LinearSolverKind::kKlu, &xk);
  ASSERT_EQ(xd.size(), xk.size());
  double diff = 0.0;
  for (size_t k = 0; k < xd.size(); ++k) diff = std::max(diff, std::abs(xd[k] - xk[k]));
  EXPECT_LE(diff, 1e-7 * (P.r + P.l));
  testing::Record("max_difference_m", diff);
}

// A cantilever (frame = clamped end, ground joint) under its own weight: the static-
// equilibrium start deflects the tip by w = ρ A g L⁴ / (8 E I) (Euler–Bernoulli, uniform
// load; Timoshenko & Gere, Mechanics of Materials, cantilever table) to 1 % with 4
// Craig–Bampton modes, and the rod then stays at rest (no start-up transient).
TEST(FlexibleRod, StaticEquilibriumStartDeflectsACantileverByQL4Over8EI) {
  const double L = 0.2, g = 9.81;
  auto rod = MakeSteelRod(L, 20, 4);
  MechanismBuilder b;
  FlexibleBodySpec fs;
  fs.name = "rod";
  fs.rod = rod;
  fs.damping = DampingSpec::FrequencyBand();
  const BodyId body = b.AddFlexibleBody(fs);
  const MarkerId tip = b.AddNodeMarker(body, "tip", rod->rod.num_nodes() - 1);
  b.AddGroundJoint("clamp", body, Vec2(0.0, 0.0), 0.0);
  b.SetGravity(Vec2(0.0, -g));
  const Mechanism m = b.Build();
  RunData data(m);
  InitialConditionSpec ic;
  ic.elastic = ElasticInitialState::kStaticEquilibrium;
  SimulationOptions opt;
  opt.t_end = 0.02;
  opt.sample_rate = 5000.0;
  const fem::RodSpec& rs = rod->rod;
  const double q = rs.material.density * rs.section.area() * g;
  const double w_exact =
      q * std::pow(L, 4) / (8.0 * rs.material.youngs_modulus * rs.section.inertia_in_plane());
  double tip_first = 0.0, tip_motion = 0.0, max_qdot = 0.0;
  bool first = true;
  SimulationCallbacks cb;
  cb.on_sample = [&](const SampleView& s) {
    const double w = s.Marker(tip).position.y();
    if (first) {
      tip_first = w;
      first = false;
    }
    tip_motion = std::max(tip_motion, std::abs(w - tip_first));
    for (int k = 0; k < m.bodies()[0].num_modes; ++k) {
      max_qdot = std::max(max_qdot, std::abs(s.velocity(m.coordinate(body, kFirstMode + k))));
    }
  };
  const SimulationStatus st = Simulate(m, &data, ic, opt, cb);
  ASSERT_TRUE(st.ok()) << st.Summary();
  EXPECT_NEAR(-tip_first, w_exact, 0.01 * w_exact);
  EXPECT_LE(tip_motion, 1e-6 * w_exact);
  testing::Record("tip_deflection_m", -tip_first);
  testing::Record("beam_formula_m", w_exact);
  testing::Record("tip_motion_rel", tip_motion / w_exact);
}

// Without the equilibrium start the same cantilever starts undeformed and vibrates: the
// comparison shows the option is what removes the transient.
TEST(FlexibleRod, UndeformedStartOfALoadedCantileverVibrates) {
  auto rod = MakeSteelRod(0.2, 20, 4);
  MechanismBuilder b;
  FlexibleBodySpec fs;
  fs.name = "rod";
  fs.rod = rod;
  const BodyId body = b.AddFlexibleBody(fs);
  const MarkerId tip = b.AddNodeMarker(body, "tip", rod->rod.num_nodes() - 1);
  b.AddGroundJoint("clamp", body, Vec2(0.0, 0.0), 0.0);
  b.SetGravity(Vec2(0.0, -9.81));
  const Mechanism m = b.Build();
  RunData data(m);
  SimulationOptions opt;
  opt.t_end = 0.02;
  opt.sample_rate = 5000.0;
  double lowest = 0.0;
  SimulationCallbacks cb;
  cb.on_sample = [&](const SampleView& s) {
    lowest = std::min(lowest, s.Marker(tip).position.y());
  };
  const SimulationStatus st = Simulate(m, &data, InitialConditionSpec{}, opt, cb);
  ASSERT_TRUE(st.ok()) << st.Summary();
  EXPECT_LT(lowest, -1e-5);  // the tip falls (and overshoots the static deflection)
}

// The velocity tolerance is loosened only where joints or elements act on elastic
// coordinates (see kElasticJointVelocityTolScale); rigid and frame-attached models keep 1.
TEST(FlexibleRod, AutomaticVelocityToleranceFollowsTheTopology) {
  SliderCrankParams P;
  EXPECT_EQ(AutoVelocityTolScale(testing::BuildRigidSliderCrank(P).model), 1.0);
  auto rod = MakeSteelRod(P.l, 10, 2);
  EXPECT_EQ(AutoVelocityTolScale(BuildFlexibleSliderCrank(P, rod).model),
            kElasticJointVelocityTolScale);
  MechanismBuilder b;
  FlexibleBodySpec fs;
  fs.name = "rod";
  fs.rod = rod;
  const BodyId body = b.AddFlexibleBody(fs);
  b.AddRevolute("pin", b.AddGroundMarker("O", Vec2::Zero()), b.AddNodeMarker(body, "base", 0));
  EXPECT_EQ(AutoVelocityTolScale(b.Build()), 1.0);  // node 0 is fixed in the frame
}

}  // namespace
}  // namespace flexrod::multibody
