// tests/multibody/clearance_element_test.cc — the clearance joint as a force element, with
// prescribed marker kinematics (no integrator): the force is exactly zero whenever the contact
// is not on; the marker loads (force at the circle centre + moment about it) are statically
// equivalent to the contact-point loads and their power is −F_n δ̇ + F_t v_t; for every one of
// the sixteen normal laws, with Coulomb and with LuGre friction, the element's energy identity
// E(t) − E(0) + ∫(D + P_mech) dt = 0 holds along a loading–unloading–separation path with a
// dissipation D_n ≥ 0 (the bookkeeping that closes a run's energy balance); onset, separation and
// maximum-penetration roots set the memory as documented.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "clearance_fixture.h"
#include "multibody/clearance_joint.h"
#include "multibody/prescribed.h"
#include "multibody/run_data.h"
#include "multibody/simulate.h"

namespace flexrod::multibody {
namespace {

using testing::RigJointGeometry;
using testing::RigLaw;

double Cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

struct Memory {
  std::vector<double> m;
  explicit Memory(const ClearanceJoint& j) : m(j.num_memory(), 0.0) {}
  double* data() { return m.data(); }
};

MarkerKinematics Kin(const Vec2& p, const Vec2& v, double w) {
  MarkerKinematics k;
  k.position = p;
  k.velocity = v;
  k.angular_velocity = w;
  return k;
}

TEST(ClearanceElement, ForceIsExactlyZeroUnlessTheContactIsOn) {
  const ClearanceJoint joint(RigJointGeometry(), RigLaw("hybrid", 0.9),
                             contact::MakeFrictionLaw("coulomb"));
  const double c = RigJointGeometry().clearance();
  Memory mem(joint);
  const MarkerKinematics bush = Kin(Vec2(0.01, 0.02), Vec2(0.3, -0.1), 2.0);
  auto eval = [&](const Vec2& e, ElementOutput* out) {
    const MarkerKinematics pin = Kin(bush.position + e, Vec2(0.5, 0.2), -3.0);
    *out = ElementOutput{};
    ASSERT_TRUE(joint.Evaluate(0.0, bush, pin, nullptr, mem.data(), out));
  };
  auto expect_zero = [](const ElementOutput& o, const char* what) {
    EXPECT_EQ(o.force_i.x(), 0.0) << what;
    EXPECT_EQ(o.force_i.y(), 0.0) << what;
    EXPECT_EQ(o.force_j.x(), 0.0) << what;
    EXPECT_EQ(o.force_j.y(), 0.0) << what;
    EXPECT_EQ(o.moment_i, 0.0) << what;
    EXPECT_EQ(o.moment_j, 0.0) << what;
    EXPECT_EQ(o.dissipation, 0.0) << what;
  };
  const Vec2 dir(std::cos(0.4), std::sin(0.4));
  ElementOutput out;
  eval(0.5 * c * dir, &out);  // open gap, flag off
  expect_zero(out, "open joint");
  eval(Vec2::Zero(), &out);  // concentric pin: normal undefined
  expect_zero(out, "concentric pin");
  eval((c + 2e-6) * dir, &out);  // penetrated but no located onset yet (inside a step)
  expect_zero(out, "penetration before the onset is located");
  mem.m[kContactFlag] = 1.0;
  mem.m[kApproachVelocity] = 0.2;
  eval((c - 1e-9) * dir, &out);  // flag on, gap re-opened (before the separation is located)
  expect_zero(out, "flag on, open gap");
  eval((c + 2e-6) * dir, &out);  // in contact
  EXPECT_GT(out.force_i.norm(), 1.0);
  EXPECT_GT(std::abs(out.moment_j), 0.0);
}

TEST(ClearanceElement, MarkerLoadsAreTheContactPointLoadsAndTheirPowerIsMinusFnRatePlusFtSlip) {
  const ClearanceJoint joint(RigJointGeometry(), RigLaw("flores", 0.7),
                             contact::MakeFrictionLaw("coulomb", {{"friction-coefficient", 0.3}}));
  const contact::ContactGeometry g = RigJointGeometry();
  Memory mem(joint);
  mem.m[kContactFlag] = 1.0;
  mem.m[kApproachVelocity] = 0.1;
  const MarkerKinematics bush = Kin(Vec2(0.1, -0.2), Vec2(0.3, 0.1), 2.0);
  const Vec2 n(std::cos(1.1), std::sin(1.1));
  const MarkerKinematics pin =
      Kin(bush.position + (g.clearance() + 3e-6) * n, bush.velocity + Vec2(0.05, 0.2), -4.0);
  ElementOutput out;
  ASSERT_TRUE(joint.Evaluate(0.0, bush, pin, nullptr, mem.data(), &out));
  const ClearanceResponse r = joint.CalcResponse(bush, pin, nullptr, mem.data());
  ASSERT_TRUE(r.in_contact);
  ASSERT_GT(r.normal_force, 10.0);
  ASSERT_LT(r.friction_force * r.kinematics.slip_velocity, 0.0);  // friction opposes slip
  EXPECT_EQ(out.force_i, Vec2(-out.force_j));
  // Moment about the world origin: marker form (force at the centre + moment) = force at the
  // contact point Q (contact/geometry.h: Q_P = p_P + R_pin n, Q_B = p_B + R_bush n).
  const Vec2 q_pin = pin.position + g.pin_radius * n, q_bush = bush.position + g.bush_radius * n;
  const double scale = r.normal_force * 0.1;
  EXPECT_NEAR(Cross(pin.position, out.force_j) + out.moment_j, Cross(q_pin, out.force_j),
              1e-12 * scale);
  EXPECT_NEAR(Cross(bush.position, out.force_i) + out.moment_i, Cross(q_bush, out.force_i),
              1e-12 * scale);
  // Power of the marker loads on the two bodies = −F_n δ̇ + F_t v_t.
  const double power = out.force_i.dot(bush.velocity) + out.moment_i * bush.angular_velocity +
                       out.force_j.dot(pin.velocity) + out.moment_j * pin.angular_velocity;
  const double expected = -r.normal_force * r.kinematics.penetration_rate +
                          r.friction_force * r.kinematics.slip_velocity;
  EXPECT_NEAR(power, expected, 1e-12 * std::abs(r.normal_force));
  EXPECT_DOUBLE_EQ(out.dissipation, r.normal_dissipation + r.friction_dissipation);
  EXPECT_GT(r.friction_dissipation, 0.0);
}

// ---- energy identity along a prescribed path, every law --------------------------------------

struct PathResult {
  double identity_error{0.0};          // E(end) − E(0) + ∫(D + P_mech) dt [J]
  double work_scale{0.0};              // ∫|P_mech| dt [J]
  double min_normal_dissipation{0.0};  // [W]
  double max_normal_dissipation{0.0};  // [W]
  double min_friction_dissipation{0.0};
  double dissipated{0.0};  // ∫ D dt [J]
  double peak_force{0.0};
};

// Bush fixed at the origin, spinning at −3 rad/s; the pin centre moves radially along n0 with
// δ(t) = δ_m sin(πt/T), t ∈ [0, 1.5T] (loading, unloading, then a 0.7 µm open gap), spinning at
// 5 rad/s (slip ≈ 0.074 m/s). States and ∫(D + P_mech) by classical RK4; the onset (t = 0),
// maximum penetration (T/2) and separation (T) are step boundaries, where OnRoot is called as
// the engine would.
PathResult RunPath(const ClearanceJoint& joint) {
  const contact::ContactGeometry g = RigJointGeometry();
  const double dm = 5e-6, T = 1e-4, c = g.clearance();
  const int steps = 3000;
  const double h = 1.5 * T / steps;
  const Vec2 n0(std::cos(0.7), std::sin(0.7));
  const MarkerKinematics bush = Kin(Vec2::Zero(), Vec2::Zero(), -3.0);
  auto pin_at = [&](double t) {
    const double w = std::numbers::pi / T;
    return Kin((c + dm * std::sin(w * t)) * n0, dm * w * std::cos(w * t) * n0, 5.0);
  };
  const int ns = joint.num_states();
  Memory mem(joint);
  std::array<double, 2> z{0.0, 0.0};
  joint.Initialize(bush, pin_at(0.0), z.data(), mem.data());
  EXPECT_EQ(mem.m[kContactFlag], 0.0);  // δ = 0 exactly: not penetrated
  EXPECT_TRUE(joint.OnRoot(0, +1, 0.0, bush, pin_at(0.0), z.data(), mem.data()));
  PathResult res;
  res.min_normal_dissipation = res.min_friction_dissipation = 1e300;
  // f = [ż, D + P_mech] at (t, z).
  auto rhs = [&](double t, const std::array<double, 2>& zz, std::array<double, 3>* f) {
    const MarkerKinematics pin = pin_at(t);
    std::array<double, 2> rates{0.0, 0.0};
    ElementOutput out;
    out.state_rates = rates.data();
    EXPECT_TRUE(joint.Evaluate(t, bush, pin, zz.data(), mem.data(), &out));
    const double p_mech = out.force_i.dot(bush.velocity) + out.moment_i * bush.angular_velocity +
                          out.force_j.dot(pin.velocity) + out.moment_j * pin.angular_velocity;
    const ClearanceResponse r = joint.CalcResponse(bush, pin, zz.data(), mem.data());
    res.min_normal_dissipation = std::min(res.min_normal_dissipation, r.normal_dissipation);
    res.max_normal_dissipation = std::max(res.max_normal_dissipation, r.normal_dissipation);
    res.min_friction_dissipation = std::min(res.min_friction_dissipation, r.friction_dissipation);
    res.peak_force = std::max(res.peak_force, r.normal_force);
    (*f)[0] = rates[0];
    (*f)[1] = rates[1];
    (*f)[2] = out.dissipation + p_mech;
    return std::abs(p_mech);
  };
  const double e0 = joint.PotentialEnergy(bush, pin_at(0.0), z.data(), mem.data());
  double w = 0.0, dissipated = 0.0;
  for (int k = 0; k < steps; ++k) {
    const double t = k * h;
    std::array<double, 3> k1, k2, k3, k4;
    auto shifted = [&](const std::array<double, 3>& f, double a) {
      std::array<double, 2> zz = z;
      for (int s = 0; s < ns; ++s) zz[s] += a * h * f[s];
      return zz;
    };
    const double p1 = rhs(t, z, &k1);
    rhs(t + 0.5 * h, shifted(k1, 0.5), &k2);
    rhs(t + 0.5 * h, shifted(k2, 0.5), &k3);
    const double p4 = rhs(t + h, shifted(k3, 1.0), &k4);
    for (int s = 0; s < ns; ++s) z[s] += h / 6.0 * (k1[s] + 2 * k2[s] + 2 * k3[s] + k4[s]);
    w += h / 6.0 * (k1[2] + 2 * k2[2] + 2 * k3[2] + k4[2]);
    res.work_scale += 0.5 * h * (p1 + p4);
    {
      const ClearanceResponse r = joint.CalcResponse(bush, pin_at(t + h), z.data(), mem.data());
      dissipated += h * r.dissipation();
    }
    if (k + 1 == steps / 3 && joint.num_roots() == 2) {  // maximum penetration at T/2
      EXPECT_TRUE(joint.OnRoot(1, -1, t + h, bush, pin_at(t + h), z.data(), mem.data()));
    }
    if (k + 1 == 2 * steps / 3) {  // separation at T
      joint.OnRoot(0, -1, t + h, bush, pin_at(t + h), z.data(), mem.data());
      EXPECT_EQ(mem.m[kContactFlag], 0.0);
    }
  }
  const double e1 = joint.PotentialEnergy(bush, pin_at(1.5 * T), z.data(), mem.data());
  res.identity_error = e1 - e0 + w;
  res.dissipated = dissipated;
  return res;
}

contact::ParameterMap PathOverrides(const std::string& law) {
  // Explicit damping where a law would otherwise calibrate it to an impact mass.
  if (law == "kelvin-voigt") return {{"damping", 2e3}};
  if (law == "maxwell" || law == "standard-linear-solid") return {{"damping", 2e4}};
  if (law == "impact") return {{"max-damping", 1e4}};
  return {};
}

TEST(ClearanceElement, EnergyIdentityClosesForEveryNormalLawWithCoulombAndLuGreFriction) {
  for (const std::string& name : contact::NormalLawNames()) {
    for (const char* friction : {"coulomb", "lugre"}) {
      SCOPED_TRACE(name + " + " + friction);
      const ClearanceJoint joint(RigJointGeometry(), RigLaw(name, 0.6, PathOverrides(name)),
                                 contact::MakeFrictionLaw(friction));
      const PathResult r = RunPath(joint);
      ASSERT_GT(r.peak_force, 100.0);  // the path really loads the contact (≈ 0.1–1 kN)
      // Stateless laws close to round-off (the identity is exact in ∂E/∂δ); Maxwell, SLS and
      // elasto-plastic paths have kinks (slack spring, clipped force, δ_p) where RK4 drops to low
      // order: their error converges with the step (≈ 1e-7 at 3000 steps, 2e-9 at 12000).
      EXPECT_LE(std::abs(r.identity_error), 1e-6 * r.work_scale)
          << "error " << r.identity_error << " J of " << r.work_scale << " J";
      // Power scale F_peak · δ̇_max (δ̇_max = π δ_m/T ≈ 0.16 m/s).
      const double power_scale = r.peak_force * 0.16;
      EXPECT_GE(r.min_normal_dissipation, -1e-9 * power_scale) << "D_n must be >= 0";
      if (std::string(friction) == "coulomb") {
        EXPECT_GE(r.min_friction_dissipation, 0.0);
      }
      const bool elastic = name == "hertz" || name == "linear-spring" || name == "esdu-78035" ||
                           name == "johnson" || name == "dubowsky-freudenstein";
      if (elastic) {
        // Only friction dissipates: the normal law returns all its energy.
        EXPECT_LE(r.max_normal_dissipation, 1e-9 * power_scale);
      } else {
        EXPECT_GT(r.max_normal_dissipation, 1e-3 * power_scale);
      }
    }
  }
}

// Stacked outputs o = [F_bush, M_bush, F_pin, M_pin, D, ż] (the ForceElement Jacobian rows).
Vec StackedOutputs(const ClearanceJoint& joint, const MarkerKinematics& bush,
                   const MarkerKinematics& pin, const double* z, const double* memory) {
  const int ns = joint.num_states();
  std::array<double, kMaxClearanceStates> rates{};
  ElementOutput out;
  out.state_rates = rates.data();
  EXPECT_TRUE(joint.Evaluate(0.0, bush, pin, z, memory, &out));
  Vec o(7 + ns);
  o << out.force_i, out.moment_i, out.force_j, out.moment_j, out.dissipation;
  for (int k = 0; k < ns; ++k) o(7 + k) = rates[k];
  return o;
}

double& KinematicInput(MarkerKinematics* k, int c) {
  double* parts[6] = {&k->position.x(), &k->position.y(), &k->velocity.x(),
                      &k->velocity.y(), &k->angle,        &k->angular_velocity};
  return *parts[c];
}

// The analytic Jacobian (forces, moments and state rates from the laws' derivatives, the
// dissipation row differenced in the law variables) against Richardson-extrapolated central
// differences of Evaluate in every kinematic input and state, for every normal law with each
// friction law and without friction: in contact while penetrating and while restoring, and with
// the contact flag on but the gap open. Steps: 1e-10 m, 1e-7 m/s, 1e-5 rad/s, 1e-3 of each
// state's scale; agreement to 1e-6 of each row's largest entry (2e-5 for the dissipation row,
// whose scale is at least 1e-6 of the force row's).
TEST(ClearanceElement, AnalyticJacobianMatchesCentralDifferencesForEveryLaw) {
  const double c = RigJointGeometry().clearance();
  std::vector<std::string> frictions = contact::FrictionLawNames();
  frictions.push_back("");
  int checked = 0;
  for (const std::string& name : contact::NormalLawNames()) {
    for (const std::string& friction : frictions) {
      std::optional<contact::FrictionLaw> fl;
      if (!friction.empty()) fl = contact::MakeFrictionLaw(friction);
      const ClearanceJoint joint(RigJointGeometry(), RigLaw(name, 0.6, PathOverrides(name)), fl);
      const int ns = joint.num_states();
      // depth [m], normal rate [m/s]: penetrating, restoring, open with the flag on.
      for (const auto& [depth, rate] : {std::pair{4e-6, 0.05}, {3.5e-6, -0.02}, {-2e-6, 0.01}}) {
        SCOPED_TRACE(name + " + " + (friction.empty() ? "no friction" : friction) + ", depth " +
                     std::to_string(depth));
        Memory mem(joint);
        mem.m[kContactFlag] = 1.0;
        mem.m[kApproachVelocity] = 0.3;
        if (name == "elasto-plastic") {  // on the unloading curve from δ_max = 5 µm
          mem.m[kMaxPenetration] = 5e-6;
          mem.m[kMaxForce] = 4e3;
        }
        std::array<double, kMaxClearanceStates> z{};
        if (joint.normal_state_index() >= 0) z[joint.normal_state_index()] = 1e-6;
        if (joint.friction_state_index() >= 0) {
          z[joint.friction_state_index()] = 0.3 * joint.StateScale(joint.friction_state_index());
        }
        const Vec2 n(std::cos(0.7), std::sin(0.7)), t(-n.y(), n.x());
        const MarkerKinematics bush = Kin(Vec2(0.01, 0.02), Vec2(0.3, -0.1), 5.0);
        const MarkerKinematics pin =
            Kin(bush.position + (c + depth) * n, bush.velocity + rate * n + 0.2 * t, -20.0);
        Mat dk = Mat::Zero(7 + ns, kElementKinematicColumns), dz = Mat::Zero(7 + ns, ns);
        ASSERT_TRUE(joint.EvaluateJacobian(0.0, bush, pin, z.data(), mem.data(), &dk, &dz));
        Mat fk(7 + ns, kElementKinematicColumns), fz(7 + ns, ns);
        for (int col = 0; col < kElementKinematicColumns; ++col) {
          const int side = col / 6, comp = col % 6;
          const double h = comp < 2 ? 1e-10 : comp < 4 ? 1e-7 : 1e-5;
          auto central = [&](double hh) {
            MarkerKinematics kp[2] = {bush, pin}, km[2] = {bush, pin};
            KinematicInput(&kp[side], comp) += hh;
            KinematicInput(&km[side], comp) -= hh;
            return Vec((StackedOutputs(joint, kp[0], kp[1], z.data(), mem.data()) -
                        StackedOutputs(joint, km[0], km[1], z.data(), mem.data())) /
                       (2.0 * hh));
          };
          fk.col(col) = (4.0 * central(0.5 * h) - central(h)) / 3.0;
        }
        for (int s = 0; s < ns; ++s) {
          const double h = 1e-3 * joint.StateScale(s);
          auto central = [&](double hh) {
            std::array<double, kMaxClearanceStates> zp = z, zm = z;
            zp[s] += hh;
            zm[s] -= hh;
            return Vec((StackedOutputs(joint, bush, pin, zp.data(), mem.data()) -
                        StackedOutputs(joint, bush, pin, zm.data(), mem.data())) /
                       (2.0 * hh));
          };
          fz.col(s) = (4.0 * central(0.5 * h) - central(h)) / 3.0;
        }
        // The dissipation of an elastic law is zero up to round-off; its row is measured
        // against the force derivatives times 1 µm/s.
        const double power_scale = 1e-6 * fk.row(3).cwiseAbs().maxCoeff();
        for (int r = 0; r < 7 + ns; ++r) {
          const double scale = std::max({fk.row(r).cwiseAbs().maxCoeff(),
                                         ns > 0 ? fz.row(r).cwiseAbs().maxCoeff() : 0.0,
                                         r == 6 ? power_scale : 1e-9});
          const double tol = (r == 6 ? 2e-5 : 1e-6) * scale;
          EXPECT_LE((dk.row(r) - fk.row(r)).cwiseAbs().maxCoeff(), tol) << "row " << r;
          if (ns > 0) {
            EXPECT_LE((dz.row(r) - fz.row(r)).cwiseAbs().maxCoeff(), tol) << "row " << r;
          }
        }
        if (depth > 0.0) {
          EXPECT_GT(fk.row(3).cwiseAbs().maxCoeff(), 1e6);  // a loaded contact
        }
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 3 * static_cast<int>(contact::NormalLawNames().size() * frictions.size()));
}

TEST(ClearanceElement, OnsetRecordsTheFlooredApproachVelocityAndResetsTheStates) {
  const ClearanceJoint joint(RigJointGeometry(), RigLaw("maxwell", 0.8, {{"damping", 2e4}}),
                             contact::MakeFrictionLaw("lugre"));
  ASSERT_EQ(joint.num_states(), 2);
  ASSERT_EQ(joint.num_roots(), 1);
  const double c = RigJointGeometry().clearance();
  Memory mem(joint);
  const MarkerKinematics bush = Kin(Vec2::Zero(), Vec2::Zero(), 0.0);
  const MarkerKinematics pin = Kin(Vec2(c, 0.0), Vec2(0.25, 0.0), 0.0);
  const std::array<double, 2> z{3e-7, -2e-6};  // states left over from an earlier contact
  double g = 0.0;
  joint.Roots(0.0, bush, pin, z.data(), mem.data(), &g);
  EXPECT_NEAR(g, -joint.EventBand(), 1e-18);  // flag off: g₀ = δ − b
  EXPECT_TRUE(joint.OnRoot(0, +1, 0.125, bush, pin, z.data(), mem.data()));
  EXPECT_EQ(mem.m[kContactFlag], 1.0);
  EXPECT_DOUBLE_EQ(mem.m[kApproachVelocity], 0.25);
  EXPECT_EQ(mem.m[kOnsetTime], 0.125);
  EXPECT_EQ(mem.m[kOnsetCount], 1.0);
  EXPECT_EQ(mem.m[kStatesAtOnset + 0], z[0]);
  EXPECT_EQ(mem.m[kStatesAtOnset + 1], z[1]);
  // Just inside: the laws see z − z_onset = 0, so the Maxwell spring carries the whole δ.
  const MarkerKinematics in = Kin(Vec2(c + 1e-6, 0.0), Vec2(0.25, 0.0), 0.0);
  const ClearanceResponse r = joint.CalcResponse(bush, in, z.data(), mem.data());
  const auto& law = std::get<contact::MaxwellLaw>(joint.normal_law());
  EXPECT_NEAR(r.normal_force, law.stiffness * 1e-6, 1e-9 * law.stiffness * 1e-6);
  // With the flag on, g₀ = δ + b: at the onset point it is 2b, far from δ's round-off.
  joint.Roots(0.0, bush, pin, z.data(), mem.data(), &g);
  EXPECT_NEAR(g, joint.EventBand(), 1e-18);
  EXPECT_GT(joint.EventBand(), 1e3 * 0.35 * std::numeric_limits<double>::epsilon());
  // A root in the flag's own direction (round-off chatter) changes nothing and asks no restart.
  EXPECT_FALSE(joint.OnRoot(0, +1, 0.13, bush, pin, z.data(), mem.data()));
  EXPECT_EQ(mem.m[kContactFlag], 1.0);
  EXPECT_EQ(mem.m[kOnsetCount], 1.0);
  EXPECT_EQ(mem.m[kOnsetTime], 0.125);
  EXPECT_TRUE(joint.OnRoot(0, -1, 0.2, bush, pin, z.data(), mem.data()));  // has states
  EXPECT_EQ(mem.m[kContactFlag], 0.0);
  EXPECT_FALSE(joint.OnRoot(0, -1, 0.21, bush, pin, z.data(), mem.data()));  // already off
  EXPECT_EQ(mem.m[kContactFlag], 0.0);

  // A hysteresis law floors a grazing approach at its minimum approach velocity.
  const ClearanceJoint hybrid(RigJointGeometry(), RigLaw("hybrid", 0.9), std::nullopt);
  Memory mh(hybrid);
  const MarkerKinematics graze = Kin(Vec2(c, 0.0), Vec2(1e-6, 0.3), 0.0);
  EXPECT_TRUE(hybrid.OnRoot(0, +1, 0.0, bush, graze, nullptr, mh.data()));
  EXPECT_DOUBLE_EQ(mh.m[kApproachVelocity], contact::kDefaultMinApproachVelocity);
  EXPECT_FALSE(hybrid.OnRoot(0, -1, 0.1, bush, graze, nullptr, mh.data()));  // stateless

  // Elasto-plastic: the second root is δ̇ in contact, 1 outside; at a maximum the history is set.
  const ClearanceJoint plastic(RigJointGeometry(), RigLaw("elasto-plastic", 0.5), std::nullopt);
  ASSERT_EQ(plastic.num_roots(), 2);
  Memory mp(plastic);
  double g2[2];
  plastic.Roots(0.0, bush, in, nullptr, mp.data(), g2);
  EXPECT_EQ(g2[1], 1.0);
  mp.m[kContactFlag] = 1.0;
  plastic.Roots(0.0, bush, in, nullptr, mp.data(), g2);
  EXPECT_DOUBLE_EQ(g2[1], 0.25);
  EXPECT_TRUE(plastic.OnRoot(1, -1, 0.0, bush, in, nullptr, mp.data()));
  const auto& ep = std::get<contact::ElastoPlasticLaw>(plastic.normal_law());
  EXPECT_NEAR(mp.m[kMaxPenetration], 1e-6, 1e-15);
  EXPECT_NEAR(mp.m[kMaxForce], ep.stiffness * std::pow(1e-6, ep.exponent), 1e-9 * mp.m[kMaxForce]);
}

// The relative tolerance of the coordinates that move the joint's markers refers to the
// clearance (ForceElement::ResolvedLength), not to their absolute values: frame positions of
// the bush and pin bodies c, the bush body's angle c / |ū| (its marker 0.3 m from the frame
// origin), the pin body's angle (marker at its origin) and every other unknown uncapped.
TEST(ClearanceJoint, CapsTheRelativeToleranceOfTheCoordinatesThatMoveItsMarkersAtTheClearance) {
  MechanismBuilder b;
  const BodyId rod = b.AddRigidBody({"rod", 0.5, 4e-3, Vec2::Zero()});
  const BodyId slider = b.AddRigidBody({"slider", 1.0, 1e-4, Vec2::Zero()});
  const MarkerId bush = b.AddBodyMarker(rod, "bush", Vec2(0.3, 0.0));
  const MarkerId pin = b.AddBodyMarker(slider, "pin", Vec2::Zero());
  const auto joint = std::make_shared<const ClearanceJoint>(RigJointGeometry(),
                                                            RigLaw("hybrid", 0.9), std::nullopt);
  b.AddForceElement("clearance", bush, pin, joint);
  const Mechanism m = b.Build();
  RunData data(m);
  PrescribedMotion pm(m, false);
  MechanismDae dae(m, &data, pm, std::nullopt);
  ASSERT_EQ(dae.size(), m.size());
  std::vector<double> caps(m.size());
  dae.RelativeToleranceCaps(caps.data());
  const double c = RigJointGeometry().clearance();
  EXPECT_DOUBLE_EQ(joint->ResolvedLength(), c);
  const double inf = std::numeric_limits<double>::infinity();
  for (int i = 0; i < m.size(); ++i) {
    double expected = inf;
    if (i == m.coordinate(rod, kX) || i == m.coordinate(rod, kY)) expected = c;
    if (i == m.coordinate(slider, kX) || i == m.coordinate(slider, kY)) expected = c;
    if (i == m.coordinate(rod, kTheta)) expected = c / 0.3;
    EXPECT_EQ(caps[i], expected) << m.VariableName(i);
  }
}

}  // namespace
}  // namespace flexrod::multibody
