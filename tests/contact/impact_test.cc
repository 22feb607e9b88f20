// tests/contact/impact_test.cc — single-impact properties: restitution of the hysteresis laws
// depends on the law alone (not on mass, stiffness, speed), elastic laws return all the energy,
// every impact dissipates non-negative energy, derived damping reaches the requested
// restitution, the loop starts and ends at zero force; bad input.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "contact/impact.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/error.h"
#include "tests/contact/contact_test_util.h"

namespace flexrod::contact {
namespace {

using testing::AllLaws;
using testing::NeededOverrides;
using testing::RigGeometry;
using testing::SteelPair;

TEST(Impact, HysteresisRestitutionDependsOnTheLawAloneNotOnMassStiffnessOrSpeed) {
  // F = Kδⁿ(1 + D̃δ̇/v₀): in units δ* = (m v₀²/K)^(1/(n+1)), t* = δ*/v₀ the motion is
  // parameter-free, so cₑ depends on D̃ (and n) only. Mass, stiffness and speed each vary over
  // three orders of magnitude.
  for (const char* name : {"lankarani-nikravesh", "hunt-crossley", "flores", "gonthier", "pereira",
                           "hybrid", "elasto-plastic"}) {
    const NormalLaw base = MakeNormalLaw(name, SteelPair(0.6), RigGeometry());
    const double e_ref = SimulateImpact(base, 1.0, 1.0).achieved_restitution;
    double k0 = 0.0;
    std::visit(
        [&](const auto& l) {
          if constexpr (requires { l.hysteresis; }) k0 = l.hysteresis.stiffness;
          if constexpr (requires { l.stiffness; }) k0 = l.stiffness;
        },
        base);
    ASSERT_GT(k0, 0.0) << name;
    for (double mass : {0.03, 30.0}) {
      EXPECT_NEAR(SimulateImpact(base, mass, 1.0).achieved_restitution, e_ref, 1e-8)
          << name << " mass " << mass;
    }
    for (double speed : {0.01, 10.0}) {
      EXPECT_NEAR(SimulateImpact(base, 1.0, speed).achieved_restitution, e_ref, 1e-8)
          << name << " speed " << speed;
    }
    for (double factor : {0.03, 30.0}) {
      const NormalLaw stiffer =
          MakeNormalLaw(name, SteelPair(0.6), RigGeometry(), {{"stiffness", factor * k0}});
      EXPECT_NEAR(SimulateImpact(stiffer, 1.0, 1.0).achieved_restitution, e_ref, 1e-8)
          << name << " stiffness x" << factor;
    }
  }
}

TEST(Impact, ElasticLawsReturnAllTheEnergy) {
  for (const char* name :
       {"linear-spring", "hertz", "esdu-78035", "johnson", "dubowsky-freudenstein"}) {
    const ImpactResult r =
        SimulateImpact(MakeNormalLaw(name, SteelPair(), RigGeometry()), 2.7, 0.6);
    EXPECT_NEAR(r.achieved_restitution, 1.0, 1e-9) << name;
    EXPECT_NEAR(r.dissipated_energy, 0.0, 1e-9 * 0.5 * 2.7 * 0.36) << name;
    // An elastic impact is symmetric under time reversal: the peak is at half the duration.
    EXPECT_NEAR(r.contact_duration, 2.0 * r.time_of_peak_penetration, 1e-9 * r.contact_duration)
        << name;
  }
}

TEST(Impact, EveryImpactDissipatesNonNegativeEnergy) {
  for (double e : {0.2, 0.8, 1.0}) {
    for (const auto& [name, law] : [&] {
           std::vector<testing::NamedLaw> laws;
           for (const std::string& n : NormalLawNames()) {
             try {
               laws.push_back(
                   {n, MakeNormalLaw(n, SteelPair(e), RigGeometry(), NeededOverrides(n))});
             } catch (const InputError&) {
               // standard-linear-solid cannot reach 0.2 with its default arm: covered elsewhere.
             }
           }
           return laws;
         }()) {
      const ImpactResult r = SimulateImpact(law, 1.0, 0.8);
      EXPECT_GE(r.dissipated_energy, -1e-10 * 0.32) << name << " e = " << e;
      EXPECT_LE(r.achieved_restitution, 1.0 + 1e-10) << name;
      EXPECT_GT(r.achieved_restitution, 0.0) << name;
    }
  }
}

TEST(Impact, DerivedDampingReachesTheRequestedRestitution) {
  // Kelvin–Voigt (non-tensile closed form inverted), Maxwell (textbook form, exact for it),
  // standard linear solid and ADAMS IMPACT (calibrated by simulation), elasto-plastic (exact).
  for (double e : {0.7, 0.95}) {
    for (const char* name :
         {"kelvin-voigt", "maxwell", "standard-linear-solid", "elasto-plastic"}) {
      const NormalLaw law =
          MakeNormalLaw(name, SteelPair(e), RigGeometry(), NeededOverrides(name, 2.5));
      EXPECT_NEAR(SimulateImpact(law, 2.5, 0.3).achieved_restitution, e, 2e-8) << name;
    }
    const NormalLaw impact =
        MakeNormalLaw("impact", SteelPair(e), RigGeometry(),
                      {{"effective-mass", 2.5}, {"calibration-velocity", 0.3}});
    EXPECT_NEAR(SimulateImpact(impact, 2.5, 0.3).achieved_restitution, e, 2e-8);
  }
}

TEST(Impact, LoopStartsAndEndsWithoutForceAndIsSampledDensely) {
  for (const auto& [name, law] : AllLaws(0.5)) {
    ImpactOptions options;
    options.num_samples = 100;
    const ImpactResult r = SimulateImpact(law, 1.0, 1.0, options);
    ASSERT_GE(r.loop.size(), 50u) << name;
    EXPECT_EQ(r.loop.front().penetration, 0.0);
    EXPECT_LE(r.loop.back().penetration, 0.0) << name;
    EXPECT_EQ(r.loop.back().force, 0.0) << name;
    EXPECT_GE(r.peak_force, r.loop[r.loop.size() / 2].force) << name;
    EXPECT_LE(r.contact_duration, r.exit_time) << name;
    for (size_t i = 1; i < r.loop.size(); ++i)
      ASSERT_GT(r.loop[i].time, r.loop[i - 1].time) << name;
  }
}

TEST(ImpactInput, NonPositiveMassOrSpeedIsRejected) {
  const NormalLaw law = MakeNormalLaw("hertz", SteelPair(), RigGeometry());
  try {
    SimulateImpact(law, 0.0, 1.0);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "mass");
  }
  try {
    SimulateImpact(law, 1.0, -2.0);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "velocity");
    EXPECT_EQ(e.value(), "-2");
  }
}

}  // namespace
}  // namespace flexrod::contact
