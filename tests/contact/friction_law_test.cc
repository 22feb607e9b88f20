// tests/contact/friction_law_test.cc — friction laws: opposing slip, their defining values
// (thresholds, Threlfall's 95 %, Stribeck limits), LuGre's steady state equal to the Stribeck
// curve (by integrating its state equation), derivatives against central differences, and
// bad input.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "contact/friction_law.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/error.h"

namespace flexrod::contact {
namespace {

constexpr double kNormal = 500.0;  // N

/// LuGre steady bristle deflection z_ss = g(v) sign(v), g = μ(v)/σ̂₀.
double SteadyBristle(const LuGreFrictionLaw& l, double v) {
  const double mu =
      l.friction_coefficient + (l.static_coefficient - l.friction_coefficient) *
                                   std::exp(-(v / l.stribeck_velocity) * (v / l.stribeck_velocity));
  return (v > 0 ? 1.0 : -1.0) * mu / l.bristle_stiffness;
}

TEST(FrictionLaw, EveryLawOpposesSlip) {
  for (const std::string& name : FrictionLawNames()) {
    const FrictionLaw law = MakeFrictionLaw(name);
    for (double v : {-2.0, -0.1, -1e-3, -3e-4, -5e-5, 5e-5, 3e-4, 1e-3, 0.1, 2.0}) {
      double z = 0.0;
      if (const auto* l = std::get_if<LuGreFrictionLaw>(&law)) z = SteadyBristle(*l, v);
      const double f = CalcFrictionForce(law, v, kNormal, z).force;
      EXPECT_LE(f * v, 0.0) << name << " v = " << v;
      if (std::abs(v) >= 1e-3) {
        EXPECT_LT(f * v, 0.0) << name << " v = " << v;
      }
    }
    EXPECT_EQ(CalcFrictionForce(law, 0.7, 0.0, 0.0).force, 0.0) << name << ": no load, no friction";
  }
}

TEST(FrictionLaw, CoulombDynamicCorrectionRampsBetweenThresholds) {
  const FrictionLaw law = MakeFrictionLaw(
      "coulomb",
      {{"friction-coefficient", 0.3}, {"stick-velocity", 1e-4}, {"slip-velocity", 1e-3}});
  EXPECT_EQ(CalcFrictionForce(law, 0.9e-4, kNormal).force, 0.0);
  EXPECT_NEAR(CalcFrictionForce(law, 5.5e-4, kNormal).force, -0.5 * 0.3 * kNormal, 1e-9);
  EXPECT_NEAR(CalcFrictionForce(law, -2e-3, kNormal).force, 0.3 * kNormal, 1e-12);
}

TEST(FrictionLaw, ThrelfallReaches95PercentAtItsVelocityScale) {
  const FrictionLaw law = MakeFrictionLaw("threlfall", {{"velocity-scale", 2e-3}});
  EXPECT_NEAR(CalcFrictionForce(law, 2e-3, kNormal).force,
              -kDefaultFrictionCoefficient * kNormal * (1.0 - std::exp(-3.0)), 1e-9);
}

TEST(FrictionLaw, StribeckStartsAtStaticAndEndsAtKineticPlusViscous) {
  const FrictionLaw law = MakeFrictionLaw(
      "stribeck",
      {{"friction-coefficient", 0.2}, {"static-coefficient", 0.35}, {"viscous-coefficient", 3.0}});
  EXPECT_NEAR(CalcFrictionForce(law, 1.0, kNormal).force, -0.2 * kNormal - 3.0, 1e-9);
  // The published static limit −F_s (v → 0⁺ of sign(v)) is that of tanh(v/v_r) as v_r → 0.
  const FrictionLaw sharp = MakeFrictionLaw("stribeck", {{"friction-coefficient", 0.2},
                                                         {"static-coefficient", 0.35},
                                                         {"viscous-coefficient", 3.0},
                                                         {"regularisation-velocity", 1e-15}});
  EXPECT_NEAR(CalcFrictionForce(sharp, 1e-12, kNormal).force, -0.35 * kNormal, 1e-6);
  // The default v_r = 1e-5 m/s: continuous through zero, within 1e-4 of the published law from
  // 5 v_r up, and the static peak (at v ≪ v_s = 1e-3 m/s) is kept.
  EXPECT_EQ(CalcFrictionForce(law, 0.0, kNormal).force, 0.0);
  for (double v : {5e-5, 2e-4, 1e-3, 0.01}) {
    const double published = -kNormal * (0.2 + 0.15 * std::exp(-(v / 1e-3) * (v / 1e-3))) - 3.0 * v;
    EXPECT_NEAR(CalcFrictionForce(law, v, kNormal).force, published, 1e-4 * std::abs(published))
        << v;
    EXPECT_NEAR(CalcFrictionForce(law, -v, kNormal).force, -published, 1e-4 * std::abs(published))
        << v;
  }
}

TEST(FrictionLaw, LuGreSteadyStateIsTheStribeckCurvePlusViscous) {
  // Integrate ż = v − |v| z/g(v) at constant v from z = 0 (RK4, ≥ 40 bristle time constants) and
  // compare the friction force with −(σ₀ g(v) + σ₂ v), σ₀ g(v) = F_n μ(v), σ₂ = σ̂₂ F_n, for the
  // published unit-mass set (Canudas de Wit et al. 1995) reached at F_n = 1 N, μ_c = 1, μ_s = 1.5.
  const FrictionLaw law =
      MakeFrictionLaw("lugre", {{"friction-coefficient", 1.0}, {"static-coefficient", 1.5}});
  const auto& l = std::get<LuGreFrictionLaw>(law);
  for (double v : {2e-4, 1e-3, 3e-3, 0.05, -1e-3}) {
    double z = 0.0;
    const double tau = 1.5 / (l.bristle_stiffness * std::abs(v));  // upper bound of g/|v|
    const int steps = 40000;
    const double h = 40.0 * tau / steps;
    auto rate = [&](double zz) { return CalcFrictionStateRate(law, v, zz).rate; };
    for (int i = 0; i < steps; ++i) {
      const double k1 = rate(z), k2 = rate(z + 0.5 * h * k1), k3 = rate(z + 0.5 * h * k2),
                   k4 = rate(z + h * k3);
      z += h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4);
    }
    const double mu = 1.0 + 0.5 * std::exp(-(v / 1e-3) * (v / 1e-3));
    const double steady = -(1.0 * mu * (v > 0 ? 1.0 : -1.0) + 0.4 * v);
    EXPECT_NEAR(CalcFrictionForce(law, v, 1.0, z).force, steady, 1e-9 * std::abs(steady))
        << "v = " << v;
  }
  // Published set: σ₀ = 1e5 N/m, σ₁ = √1e5 N·s/m at F_n = 1 N.
  EXPECT_EQ(l.bristle_stiffness, 1e5);
  EXPECT_NEAR(l.bristle_damping, std::sqrt(1e5), 1e-12);
  EXPECT_EQ(l.viscous_coefficient, 0.4);
  EXPECT_EQ(NumFrictionStates(law), 1);
}

TEST(FrictionLaw, DerivativesMatchCentralDifferences) {
  for (const std::string& name : FrictionLawNames()) {
    const FrictionLaw law = MakeFrictionLaw(name);
    for (double v : {-0.3, -4e-4, -1e-5, 3e-6, 6e-4, 2e-3, 0.8}) {  // ±1e-5: inside tanh(v/v_r)
      for (double z : {0.0, 3e-7, -1e-6}) {
        const FrictionForce f = CalcFrictionForce(law, v, kNormal, z);
        const double hv = 1e-7 * std::abs(v);
        const double fd_v = (CalcFrictionForce(law, v + hv, kNormal, z).force -
                             CalcFrictionForce(law, v - hv, kNormal, z).force) /
                            (2 * hv);
        const double fd_n = (CalcFrictionForce(law, v, kNormal + 1.0, z).force -
                             CalcFrictionForce(law, v, kNormal - 1.0, z).force) /
                            2.0;
        const double hz = 1e-9;
        const double fd_z = (CalcFrictionForce(law, v, kNormal, z + hz).force -
                             CalcFrictionForce(law, v, kNormal, z - hz).force) /
                            (2 * hz);
        const double scale = std::abs(f.d_slip) + std::abs(f.force / v) + 1e-9;
        EXPECT_NEAR(f.d_slip, fd_v, 1e-5 * scale) << name << " v " << v << " z " << z;
        EXPECT_NEAR(f.d_normal, fd_n, 1e-8 * (std::abs(f.d_normal) + 1e-9)) << name;
        EXPECT_NEAR(f.d_state, fd_z, 1e-6 * (std::abs(f.d_state) + 1e-9)) << name;
        const FrictionStateRate r = CalcFrictionStateRate(law, v, z);
        const double fdr_v = (CalcFrictionStateRate(law, v + hv, z).rate -
                              CalcFrictionStateRate(law, v - hv, z).rate) /
                             (2 * hv);
        const double fdr_z = (CalcFrictionStateRate(law, v, z + hz).rate -
                              CalcFrictionStateRate(law, v, z - hz).rate) /
                             (2 * hz);
        EXPECT_NEAR(r.d_slip, fdr_v, 1e-5 * (std::abs(r.d_slip) + 1.0)) << name;
        EXPECT_NEAR(r.d_state, fdr_z, 1e-6 * (std::abs(r.d_state) + 1e-9)) << name;
      }
    }
  }
}

TEST(FrictionLawInput, BadNamesKeysAndThresholdsAreRejected) {
  try {
    MakeFrictionLaw("dahl");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "contact.friction");
    EXPECT_NE(e.rule().find("lugre"), std::string::npos);
  }
  try {
    MakeFrictionLaw("coulomb", {{"bristle-stiffness", 1e4}});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "bristle-stiffness");
    EXPECT_EQ(e.value(), "10000");
  }
  EXPECT_THROW(MakeFrictionLaw("coulomb", {{"stick-velocity", 1e-3}, {"slip-velocity", 1e-4}}),
               InputError);
  EXPECT_THROW(MakeFrictionLaw("stribeck", {{"friction-coefficient", -0.1}}), InputError);
  EXPECT_THROW(
      MakeFrictionLaw("lugre", {{"friction-coefficient", 0.3}, {"static-coefficient", 0.2}}),
      InputError);
}

}  // namespace
}  // namespace flexrod::contact
