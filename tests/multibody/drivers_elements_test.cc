// tests/multibody/drivers_elements_test.cc — drivers, force elements and joint reactions
// against closed-form solutions: speed-profile driver (exact integral, torque = I α), DC
// motor spin-up (first-order response), viscous guide damping (exponential decay), Coulomb
// guide friction (constant deceleration), spring-damper and rotational-spring oscillators,
// the reaction forces of revolute, ground and weld joints, and which oscillator's unknowns the
// integrator reports as setting the step.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "mb_test_util.h"
#include "multibody/outputs.h"
#include "multibody/simulate.h"

namespace flexrod::multibody {
namespace {

SimulationOptions TightOptions(double t_end, double rate = 1000.0) {
  SimulationOptions opt;
  opt.t_end = t_end;
  opt.sample_rate = rate;
  opt.integrator.rel_tol = 1e-10;
  opt.integrator.abs_tol = 1e-12;
  return opt;
}

// A disc of inertia I pinned at its centre (the frame origin).
struct Disc {
  MechanismBuilder builder;
  BodyId body;
  MarkerId centre, ground;
  explicit Disc(double inertia) {
    body = builder.AddRigidBody({"disc", 1.0, inertia, Vec2(0.0, 0.0)});
    ground = builder.AddGroundMarker("O", Vec2(0.0, 0.0));
    centre = builder.AddBodyMarker(body, "disc.O", Vec2(0.0, 0.0));
    builder.AddRevolute("axle", ground, centre);
  }
};

// ω(t): 0 → 30 rad/s over 0.1 s, hold to 0.3 s, down to 10 rad/s at 0.4 s, hold.
// θ(t) = θ0 + ∫ω: 150 t², 1.5 + 30 (t − 0.1), 7.5 + 30 (t − 0.3) − 100 (t − 0.3)², 9.5 + 10 (t −
// 0.4).
TEST(Drivers, SpeedProfileIsIntegratedExactlyAndItsTorqueIsInertiaTimesAcceleration) {
  const double I = 0.01, theta0 = 0.2;
  Disc d(I);
  const DriverId drv = d.builder.AddSpeedProfileDriver(
      "profile", d.body, theta0, {0.0, 0.1, 0.3, 0.4}, {0.0, 30.0, 30.0, 10.0});
  const Mechanism m = d.builder.Build();
  RunData data(m);
  auto exact = [&](double t, double* w, double* a) {
    if (t < 0.1) {
      *w = 300.0 * t;
      *a = 300.0;
      return theta0 + 150.0 * t * t;
    }
    if (t < 0.3) {
      *w = 30.0;
      *a = 0.0;
      return theta0 + 1.5 + 30.0 * (t - 0.1);
    }
    if (t < 0.4) {
      const double s = t - 0.3;
      *w = 30.0 - 200.0 * s;
      *a = -200.0;
      return theta0 + 7.5 + 30.0 * s - 100.0 * s * s;
    }
    *w = 10.0;
    *a = 0.0;
    return theta0 + 9.5 + 10.0 * (t - 0.4);
  };
  double err_theta = 0.0, err_omega = 0.0, err_torque = 0.0;
  SimulationCallbacks cb;
  cb.on_sample = [&](const SampleView& s) {
    double w = 0.0, a = 0.0;
    const double th = exact(s.t(), &w, &a);
    const DriverState ds = s.Driver(drv);
    err_theta = std::max(err_theta, std::abs(ds.angle - th));
    err_omega = std::max(err_omega, std::abs(ds.speed - w));
    // Skip samples on the knots, where α jumps.
    const double frac = std::fmod(s.t() + 1e-9, 0.1);
    if (frac > 2e-3) err_torque = std::max(err_torque, std::abs(ds.torque - I * a));
  };
  const SimulationStatus st = Simulate(m, &data, InitialConditionSpec{}, TightOptions(0.5), cb);
  ASSERT_TRUE(st.ok()) << st.Summary();
  EXPECT_LE(err_theta, 1e-9);
  EXPECT_LE(err_omega, 1e-8);
  EXPECT_LE(err_torque, 1e-6 * I * 300.0);
  EXPECT_EQ(st.stats.reinitialisations, 3);  // one restart per knot inside the run
  testing::Record("theta_error_rad", err_theta);
  testing::Record("torque_error_Nm", err_torque);
}

// J ω̇ = r T_s (1 − r ω/ω_nl), J = I + J_fw + r² J_rotor ⇒ ω = ω_ss (1 − e^{−t/τ}),
// ω_ss = ω_nl / r, τ = J ω_nl / (r² T_s).
TEST(Drivers, DcMotorSpinUpFollowsTheFirstOrderResponse) {
  const double I = 0.01;
  Disc d(I);
  DcMotorSpec motor;
  motor.stall_torque = 2.0;
  motor.no_load_speed = 300.0;
  motor.ratio = 3.0;
  motor.flywheel_inertia = 0.02;
  motor.rotor_inertia = 1e-4;
  const DriverId drv = d.builder.AddDcMotorDriver("dc", d.body, motor);
  const Mechanism m = d.builder.Build();
  RunData data(m);
  const double J = I + 0.02 + 9.0 * 1e-4;
  const double w_ss = 100.0, tau = J * 300.0 / (9.0 * 2.0);
  EXPECT_NEAR(m.bodies()[0].J0, J, 1e-15);
  double err_w = 0.0, err_th = 0.0, err_T = 0.0, worst_balance = 0.0;
  SimulationCallbacks cb;
  cb.on_sample = [&](const SampleView& s) {
    const double t = s.t(), e = std::exp(-t / tau);
    const DriverState ds = s.Driver(drv);
    err_w = std::max(err_w, std::abs(ds.speed - w_ss * (1.0 - e)));
    err_th = std::max(err_th, std::abs(ds.angle - w_ss * (t - tau * (1.0 - e))));
    err_T = std::max(err_T, std::abs(ds.torque - 3.0 * 2.0 * (1.0 - 3.0 * ds.speed / 300.0)));
    worst_balance = std::max(worst_balance, std::abs(s.Energies().balance_error));
  };
  const SimulationStatus st = Simulate(m, &data, InitialConditionSpec{}, TightOptions(1.0), cb);
  ASSERT_TRUE(st.ok()) << st.Summary();
  EXPECT_LE(err_w, 1e-6 * w_ss);
  EXPECT_LE(err_th, 1e-6 * w_ss);
  EXPECT_LE(err_T, 1e-12);
  EXPECT_LE(worst_balance, 1e-6 * 0.5 * J * w_ss * w_ss);  // driver work = ½ J ω²
  testing::Record("speed_error_rel", err_w / w_ss);
}

// A slider of mass m on a guide along x (a ground marker, axis x).
struct Slider {
  MechanismBuilder builder;
  BodyId body;
  MarkerId guide, slider;
  JointId joint;
  Slider(double mass, double damping, double friction, double v_reg) {
    body = builder.AddRigidBody({"slider", mass, 1e-3, Vec2(0.0, 0.0)});
    guide = builder.AddGroundMarker("guide", Vec2(0.0, 0.0));
    slider = builder.AddBodyMarker(body, "slider.O", Vec2(0.0, 0.0));
    PrismaticSpec ps;
    ps.name = "guide";
    ps.marker_i = guide;
    ps.marker_j = slider;
    ps.damping = damping;
    ps.friction_force = friction;
    ps.friction_regularisation_speed = v_reg;
    joint = builder.AddPrismatic(ps);
  }
};

InitialConditionSpec MovingAlongX(const Mechanism& m, BodyId body, double x0, double v0) {
  InitialConditionSpec ic;
  ic.coordinates = Vec::Zero(m.num_coordinates());
  ic.velocities = Vec::Zero(m.num_coordinates());
  ic.coordinates(m.coordinate(body, kX)) = x0;
  ic.velocities(m.coordinate(body, kX)) = v0;
  ic.fixed_velocities = {m.coordinate(body, kX)};
  return ic;
}

// m ẍ = −c ẋ ⇒ ẋ = v0 e^{−ct/m}, x = v0 m/c (1 − e^{−ct/m}); dissipated = ½ m (v0² − ẋ²).
TEST(ForceElements, ViscousGuideDampingDecaysExponentially) {
  const double mass = 2.0, c = 4.0, v0 = 3.0;
  Slider s(mass, c, 0.0, 1e-3);
  const Mechanism m = s.builder.Build();
  RunData data(m);
  const int ix = m.coordinate(s.body, kX);
  double err_v = 0.0, err_x = 0.0, err_e = 0.0;
  SimulationCallbacks cb;
  cb.on_sample = [&](const SampleView& sv) {
    const double e = std::exp(-c * sv.t() / mass);
    err_v = std::max(err_v, std::abs(sv.velocity(ix) - v0 * e));
    err_x = std::max(err_x, std::abs(sv.coordinate(ix) - v0 * mass / c * (1.0 - e)));
    const double diss = 0.5 * mass * (v0 * v0 - v0 * v0 * e * e);
    err_e = std::max(err_e, std::abs(sv.Energies().dissipated_elements - diss));
  };
  const SimulationStatus st =
      Simulate(m, &data, MovingAlongX(m, s.body, 0.0, v0), TightOptions(1.0), cb);
  ASSERT_TRUE(st.ok()) << st.Summary();
  EXPECT_LE(err_v, 1e-7 * v0);
  EXPECT_LE(err_x, 1e-7 * v0 * mass / c);
  EXPECT_LE(err_e, 1e-7 * 0.5 * mass * v0 * v0);
}

// F = F_c tanh(v/v_reg) ≈ F_c for v >> v_reg: constant deceleration F_c/m until the stop.
TEST(ForceElements, CoulombGuideFrictionDeceleratesAtConstantRate) {
  const double mass = 2.0, Fc = 5.0, v0 = 3.0;
  Slider s(mass, 0.0, Fc, 1e-4);
  const Mechanism m = s.builder.Build();
  RunData data(m);
  const int ix = m.coordinate(s.body, kX);
  double err_v = 0.0;
  SimulationCallbacks cb;
  cb.on_sample = [&](const SampleView& sv) {
    err_v = std::max(err_v, std::abs(sv.velocity(ix) - (v0 - Fc / mass * sv.t())));
  };
  // Stops at t = m v0 / F_c = 1.2 s; compare up to 1.0 s (v >= 0.5 m/s >> v_reg).
  const SimulationStatus st =
      Simulate(m, &data, MovingAlongX(m, s.body, 0.0, v0), TightOptions(1.0), cb);
  ASSERT_TRUE(st.ok()) << st.Summary();
  EXPECT_LE(err_v, 1e-7 * v0);
}

// Slider on x, spring from (−0.5, 0) with L0 = 0.4, k = 800 N/m, m = 2 kg: ω = 20 rad/s,
// x(t) = −0.1 + 0.1 cos ωt from x(0) = 0 at rest.
TEST(ForceElements, SpringOscillatesAtItsNaturalFrequency) {
  const double mass = 2.0, k = 800.0, L0 = 0.4;
  Slider s(mass, 0.0, 0.0, 1e-3);
  const MarkerId anchor = s.builder.AddGroundMarker("anchor", Vec2(-0.5, 0.0));
  s.builder.AddSpringDamper("spring", anchor, s.slider, k, 0.0, L0);
  const Mechanism m = s.builder.Build();
  RunData data(m);
  const int ix = m.coordinate(s.body, kX);
  const double w = std::sqrt(k / mass);
  double err = 0.0, worst_balance = 0.0;
  SimulationCallbacks cb;
  cb.on_sample = [&](const SampleView& sv) {
    err = std::max(err, std::abs(sv.coordinate(ix) - (-0.1 + 0.1 * std::cos(w * sv.t()))));
    worst_balance = std::max(worst_balance, std::abs(sv.Energies().balance_error));
  };
  const SimulationStatus st =
      Simulate(m, &data, MovingAlongX(m, s.body, 0.0, 0.0), TightOptions(1.0), cb);
  ASSERT_TRUE(st.ok()) << st.Summary();
  EXPECT_LE(err, 1e-7 * 0.1);
  EXPECT_LE(worst_balance, 1e-7 * 0.5 * k * 0.01);  // stored energy ½ k (0.1)²
}

// Disc (I = 0.01) with a torsion spring k = 2 N m/rad to ground: θ = θ0 cos(√(k/I) t).
TEST(ForceElements, RotationalSpringOscillatesAtItsNaturalFrequency) {
  const double I = 0.01, k = 2.0, theta0 = 0.3;
  Disc d(I);
  d.builder.AddRotationalSpringDamper("torsion", d.ground, d.centre, k, 0.0, 0.0);
  const Mechanism m = d.builder.Build();
  RunData data(m);
  InitialConditionSpec ic;
  ic.coordinates = Vec::Zero(m.num_coordinates());
  ic.coordinates(m.coordinate(d.body, kTheta)) = theta0;
  ic.fixed_coordinates = {m.coordinate(d.body, kTheta)};
  const int ith = m.coordinate(d.body, kTheta);
  const double w = std::sqrt(k / I);
  double err = 0.0;
  SimulationCallbacks cb;
  cb.on_sample = [&](const SampleView& sv) {
    err = std::max(err, std::abs(sv.coordinate(ith) - theta0 * std::cos(w * sv.t())));
  };
  const SimulationStatus st = Simulate(m, &data, ic, TightOptions(1.0), cb);
  ASSERT_TRUE(st.ok()) << st.Summary();
  EXPECT_LE(err, 1e-7 * theta0);
}

// A uniform bar (m, L) pinned at one end, released horizontal from rest: α = −3g/(2L) and
// the pin reaction is m g / 4 upward (Meriam & Kraige, Dynamics, sample problem on
// non-centroidal rotation).
TEST(JointReactions, HorizontalBarReleasedFromRestLoadsItsPinWithAQuarterOfItsWeight) {
  const double mass = 1.5, L = 0.6, g = 9.81;
  MechanismBuilder b;
  const BodyId bar = b.AddRigidBody({"bar", mass, mass * L * L / 12.0, Vec2(0.5 * L, 0.0)});
  const MarkerId pin = b.AddGroundMarker("pin", Vec2(0.0, 0.0));
  const MarkerId end = b.AddBodyMarker(bar, "bar.end", Vec2(0.0, 0.0));
  const JointId joint = b.AddRevolute("pin", pin, end);
  b.SetGravity(Vec2(0.0, -g));
  const Mechanism m = b.Build();
  RunData data(m);
  const ConsistentState s = ComputeConsistentState(m, &data, 0.0, InitialConditionSpec{});
  UpdateKinematics(m, &data, s.y.data());
  const JointReaction r = CalcJointReaction(m, data, joint, s.y.data());
  EXPECT_NEAR(r.force_j.x(), 0.0, 1e-12);
  EXPECT_NEAR(r.force_j.y(), 0.25 * mass * g, 1e-12);   // on the bar
  EXPECT_NEAR(r.force_i.y(), -0.25 * mass * g, 1e-12);  // on the ground
  EXPECT_NEAR(s.yp(m.num_coordinates() + m.coordinate(bar, kTheta)), -1.5 * g / L, 1e-12);
}

// Static equilibrium under gravity: a grounded body and a welded body carry their weight,
// and the reaction moment balances the weight's moment about the joint point.
TEST(JointReactions, GroundAndWeldJointsCarryWeightAndMoment) {
  const double g = 9.81;
  MechanismBuilder b;
  const Vec2 c1(0.1, 0.03), c2(-0.05, 0.02);
  const BodyId fixed = b.AddRigidBody({"fixed", 2.0, 0.01, c1});
  const BodyId welded = b.AddRigidBody({"welded", 0.7, 0.004, c2});
  const MarkerId w_ground = b.AddGroundMarker("weld.ground", Vec2(0.1, 0.2), 0.3);
  const MarkerId w_body = b.AddBodyMarker(welded, "welded.M", Vec2(0.05, 0.0), 0.1);
  const JointId gj = b.AddGroundJoint("ground", fixed, Vec2(0.3, -0.1), 0.4);
  const JointId wj = b.AddWeld("weld", w_ground, w_body, 0.0);
  b.SetGravity(Vec2(0.0, -g));
  const Mechanism m = b.Build();
  RunData data(m);
  InitialConditionSpec ic;
  ic.coordinates = Vec::Zero(m.num_coordinates());
  SetBodyPose(m, welded, Vec2(0.0, 0.2), 0.3, &ic.coordinates);  // near its welded pose
  const ConsistentState s = ComputeConsistentState(m, &data, 0.0, ic);
  UpdateKinematics(m, &data, s.y.data());
  auto rot = [](double a, const Vec2& v) {
    return Vec2(std::cos(a) * v.x() - std::sin(a) * v.y(),
                std::sin(a) * v.x() + std::cos(a) * v.y());
  };
  // Ground joint: force on the body at its frame origin = +m g up; moment = −(A c) × F_g.
  const JointReaction rg = CalcJointReaction(m, data, gj, s.y.data());
  EXPECT_NEAR(rg.force_j.x(), 0.0, 1e-12);
  EXPECT_NEAR(rg.force_j.y(), 2.0 * g, 1e-12);
  EXPECT_NEAR(rg.moment_j, 2.0 * g * rot(0.4, c1).x(), 1e-12);
  // Weld: body angle = 0.3 − 0.1 = 0.2; reaction at the body marker balances the weight.
  const double th = s.y(m.coordinate(welded, kTheta));
  EXPECT_NEAR(th, 0.2, 1e-12);
  const JointReaction rw = CalcJointReaction(m, data, wj, s.y.data());
  EXPECT_NEAR(rw.force_j.y(), 0.7 * g, 1e-12);
  const Vec2 lever = rot(th, c2 - Vec2(0.05, 0.0));  // marker → centre of mass
  EXPECT_NEAR(rw.moment_j, 0.7 * g * lever.x(), 1e-12);
}

// Two sliders, a and b, on parallel guides, each on a spring to ground and released 0.1 m from
// equilibrium: ω_fast = 200 rad/s, ω_slow = 20 rad/s. A BDF method of order k has a local error
// of about C (h ω)^(k+1) times the amplitude in x and ω times that in ẋ, so at one step size the
// fast slider's error exceeds the slow one's by (ω_fast / ω_slow)^(k+1) >= 100, and the fast
// slider's unknowns must set (nearly) every step; exchanging the springs must move the count to
// the other slider. One count per step: the counts add up to the steps.
TEST(StepLimiting, TheFasterOscillatorSetsTheStep) {
  for (const bool a_is_fast : {true, false}) {
    MechanismBuilder b;
    const double mass = 2.0, k_slow = 800.0, k_fast = 80000.0, L0 = 0.4;
    for (const char* name : {"a", "b"}) {
      const double y = name[0] == 'a' ? 0.0 : 1.0;
      const BodyId body = b.AddRigidBody({name, mass, 1e-3, Vec2(0.0, y)});
      const MarkerId guide = b.AddGroundMarker(std::string(name) + ".guide", Vec2(0.0, y));
      const MarkerId slider = b.AddBodyMarker(body, std::string(name) + ".O", Vec2(0.0, 0.0));
      PrismaticSpec ps;
      ps.name = std::string(name) + ".guide";
      ps.marker_i = guide;
      ps.marker_j = slider;
      b.AddPrismatic(ps);
      const MarkerId anchor = b.AddGroundMarker(std::string(name) + ".anchor", Vec2(-0.5, y));
      const bool fast = (name[0] == 'a') == a_is_fast;
      b.AddSpringDamper(std::string(name) + ".spring", anchor, slider, fast ? k_fast : k_slow, 0.0,
                        L0);
    }
    const Mechanism m = b.Build();
    RunData data(m);
    InitialConditionSpec ic;
    ic.coordinates = Vec::Zero(m.num_coordinates());
    ic.velocities = Vec::Zero(m.num_coordinates());
    for (int body : {0, 1}) {
      ic.coordinates(m.coordinate(BodyId{body}, kY)) = body == 0 ? 0.0 : 1.0;
      ic.fixed_coordinates.push_back(m.coordinate(BodyId{body}, kX));
      ic.fixed_velocities.push_back(m.coordinate(BodyId{body}, kX));
    }
    SimulationOptions opt;
    opt.t_end = 0.5;
    opt.sample_rate = 100.0;
    opt.integrator.count_step_limiting = true;
    const SimulationStatus st = Simulate(m, &data, ic, opt, SimulationCallbacks{});
    ASSERT_TRUE(st.ok()) << st.Summary();
    ASSERT_FALSE(st.step_limiting.empty());
    const std::string fast = a_is_fast ? "[a." : "[b.";
    long total = 0, by_fast = 0;
    for (const auto& [name, steps] : st.step_limiting) {
      total += steps;
      if (name.find(fast) != std::string::npos) by_fast += steps;
    }
    EXPECT_EQ(total, st.stats.steps);
    EXPECT_NE(st.step_limiting.front().first.find(fast), std::string::npos)
        << st.step_limiting.front().first;
    EXPECT_GE(static_cast<double>(by_fast), 0.9 * static_cast<double>(total))
        << by_fast << " of " << total << " steps";
  }
  // Not asked for: nothing counted.
  Slider s(2.0, 0.0, 0.0, 1e-3);
  const Mechanism m = s.builder.Build();
  RunData data(m);
  const SimulationStatus st = Simulate(m, &data, MovingAlongX(m, s.body, 0.0, 1.0),
                                       TightOptions(0.1), SimulationCallbacks{});
  ASSERT_TRUE(st.ok()) << st.Summary();
  EXPECT_TRUE(st.step_limiting.empty());
}

}  // namespace
}  // namespace flexrod::multibody
