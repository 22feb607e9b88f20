// tests/contact/impact_reftest.cc — single impacts against analytic solutions: Hertz
// (peak penetration and duration), the linear spring, Kelvin–Voigt (non-tensile closed form and
// its textbook light-damping limit), Maxwell (textbook formula, exact for it); the hysteresis
// family's damping factors against their published forms and the exact restitution relation
// (Hunt & Crossley 1975, Gonthier et al. 2004); and the achieved-versus-input restitution
// table of the hysteresis family, printed for the record, asserting the known behaviour
// (Flores close over the whole range, Lankarani–Nikravesh only near 1).
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <variant>

#include "contact/impact.h"
#include "tests/contact/contact_test_util.h"

namespace flexrod::contact {
namespace {

using testing::RigGeometry;
using testing::SteelPair;

TEST(ImpactReference, ElasticHertzPeakPenetrationAndDuration) {
  // Energy: ½mv₀² = K δ_max^(5/2)/(5/2) ⇒ δ_max = (5mv₀²/(4K))^(2/5).
  // Duration: T = 2∫₀^δmax dδ/v = (4/5) B(2/5, 1/2) δ_max/v₀ = 2.9432752 δ_max/v₀
  // (Goldsmith, Impact, 1960; the constant is recomputed here from Γ).
  const double constant = 0.8 * std::tgamma(0.4) * std::tgamma(0.5) / std::tgamma(0.9);
  EXPECT_NEAR(constant, 2.9432752, 1e-7);
  for (double k : {1e8, 6e10}) {
    for (double mass : {0.5, 3.0}) {
      for (double v0 : {0.05, 2.0}) {
        const NormalLaw law =
            MakeNormalLaw("hertz", SteelPair(), RigGeometry(), {{"stiffness", k}});
        const ImpactResult r = SimulateImpact(law, mass, v0);
        const double dmax = std::pow(5.0 * mass * v0 * v0 / (4.0 * k), 0.4);
        EXPECT_NEAR(r.peak_penetration, dmax, 1e-4 * dmax);
        EXPECT_NEAR(r.contact_duration, constant * dmax / v0, 1e-4 * constant * dmax / v0);
        EXPECT_NEAR(r.peak_force, k * std::pow(dmax, 1.5), 1e-4 * k * std::pow(dmax, 1.5));
        // The integrator does far better than the 1e-4 asked for.
        EXPECT_NEAR(r.peak_penetration, dmax, 1e-9 * dmax);
        EXPECT_NEAR(r.contact_duration, constant * dmax / v0, 1e-9 * constant * dmax / v0);
      }
    }
  }
}

TEST(ImpactReference, LinearSpringIsAHalfPeriodOfTheOscillator) {
  const double k = 3e8, m = 1.7, v0 = 0.4;
  const ImpactResult r = SimulateImpact(
      MakeNormalLaw("linear-spring", SteelPair(), RigGeometry(), {{"stiffness", k}}), m, v0);
  EXPECT_NEAR(r.contact_duration, std::numbers::pi * std::sqrt(m / k), 1e-10 * std::sqrt(m / k));
  EXPECT_NEAR(r.peak_penetration, v0 * std::sqrt(m / k), 1e-10 * v0 * std::sqrt(m / k));
}

TEST(ImpactReference, KelvinVoigtRestitutionFollowsTheNonTensileClosedForm) {
  // ζ = d/(2√(km)). The force may not pull, so contact ends when kδ + dδ̇ = 0:
  // cₑ = exp(−2ζ arccos ζ/√(1−ζ²)) (ζ < 1), exp(−2ζ arccosh ζ/√(ζ²−1)) (ζ > 1).
  const double k = 2e8, m = 1.3;
  for (double zeta : {0.01, 0.05, 0.2, 0.5, 0.9, 1.5, 4.0}) {
    const double d = 2.0 * zeta * std::sqrt(k * m);
    const NormalLaw law = MakeNormalLaw("kelvin-voigt", SteelPair(), RigGeometry(),
                                        {{"stiffness", k}, {"damping", d}});
    const ImpactResult r = SimulateImpact(law, m, 0.7);
    double expected;
    if (zeta < 1.0) {
      expected = std::exp(-2.0 * zeta * std::acos(zeta) / std::sqrt(1 - zeta * zeta));
    } else {
      expected = std::exp(-2.0 * zeta * std::acosh(zeta) / std::sqrt(zeta * zeta - 1));
    }
    EXPECT_NEAR(r.achieved_restitution, expected, 1e-9) << "zeta " << zeta;
    EXPECT_NEAR(KelvinVoigtRestitution(zeta), expected, 1e-15);
    // The textbook exp(−πζ/√(1−ζ²)) (a wall that may pull) is the light-damping limit:
    // the ratio is exp(2ζ arcsin ζ/√(1−ζ²)) = 1 + 2ζ² + (10/3)ζ⁴ + O(ζ⁶).
    if (zeta <= 0.05) {
      const double textbook = std::exp(-std::numbers::pi * zeta / std::sqrt(1 - zeta * zeta));
      const double ratio = r.achieved_restitution / textbook;
      EXPECT_NEAR(ratio, std::exp(2 * zeta * std::asin(zeta) / std::sqrt(1 - zeta * zeta)), 1e-9);
      EXPECT_NEAR(ratio - 1.0, 2.0 * zeta * zeta, 4.0 * std::pow(zeta, 4)) << "zeta " << zeta;
      EXPECT_NEAR(LinearOscillatorRestitution(zeta), textbook, 1e-15);
    }
  }
}

TEST(ImpactReference, MaxwellRestitutionIsTheTextbookFormula) {
  // Spring k in series with dashpot d: the spring stretch s obeys s̈ + (k/d)ṡ + (k/m)s = 0, and
  // the contact ends when s returns to zero: cₑ = exp(−πζ/√(1−ζ²)), ζ = √(km)/(2d).
  const double k = 5e8, m = 0.8;
  for (double zeta : {0.02, 0.2, 0.6, 0.9}) {
    const double d = std::sqrt(k * m) / (2.0 * zeta);
    const NormalLaw law =
        MakeNormalLaw("maxwell", SteelPair(), RigGeometry(), {{"stiffness", k}, {"damping", d}});
    EXPECT_NEAR(SimulateImpact(law, m, 1.1).achieved_restitution,
                std::exp(-std::numbers::pi * zeta / std::sqrt(1 - zeta * zeta)), 1e-9)
        << "zeta " << zeta;
  }
}

TEST(ImpactReference, ElastoPlasticRestitutionIsExactlyTheInput) {
  // Lankarani & Nikravesh 1994: δ_p = δ_max(1 − cₑ²) returns cₑ² of the absorbed energy.
  for (double e : {0.1, 0.5, 0.9, 0.99}) {
    const ImpactResult r =
        SimulateImpact(MakeNormalLaw("elasto-plastic", SteelPair(e), RigGeometry()), 1.0, 1.0);
    EXPECT_NEAR(r.achieved_restitution, e, 1e-9) << e;
  }
}

/// The restitution a hysteresis law F = K δⁿ (1 + D̃ δ̇/v₀) achieves, exactly: with u = δ̇/v₀,
/// m v₀² u du/dδ = −K δⁿ (1 + D̃u) separates, and ∫δⁿ dδ over the impact (0 → δ_max → 0)
/// vanishes, so ∫₁^(−e*) u/(1 + D̃u) du = 0, i.e. ln((1 + D̃)/(1 − D̃e*)) = D̃(1 + e*)
/// (Hunt & Crossley 1975, Gonthier et al. 2004, eq. for the exact restitution), whatever K, n,
/// m and v₀. The root lies below 1/D̃, so the force never pulls. Solved by bisection.
double ExactHysteresisRestitution(double damping_factor) {
  const double D = damping_factor;
  double lo = 0.0, hi = std::min(1.0, 1.0 / D);
  for (int k = 0; k < 200; ++k) {
    const double e = 0.5 * (lo + hi);
    (std::log((1.0 + D) / (1.0 - D * e)) > D * (1.0 + e) ? hi : lo) = e;
  }
  return 0.5 * (lo + hi);
}

// Each law's damping factor is its published closed form in cₑ (contact-models.md), and the
// simulated impact returns the restitution the exact relation above gives for that factor.
// The relation then shows each form's known accuracy: Hunt–Crossley's 3(1 − cₑ)/2 is the
// first-order inversion near cₑ = 1 (error O((1 − cₑ)²)); Gonthier's (1 − cₑ²)/cₑ is accurate
// at low restitution and 4/3 too dissipative near 1; Lankarani–Nikravesh only near 1.
TEST(ImpactReference, HysteresisLawsHaveTheirPublishedFactorsAndTheExactRestitution) {
  struct Form {
    const char* law;
    double (*factor)(double e);
  };
  const Form forms[] = {
      {"lankarani-nikravesh", [](double e) { return 0.75 * (1.0 - e * e); }},  // L&N 1990
      {"hunt-crossley", [](double e) { return 1.5 * (1.0 - e); }},             // H&C 1975
      {"flores", [](double e) { return 1.6 * (1.0 - e) / e; }},                // Flores 2011
      {"gonthier", [](double e) { return (1.0 - e * e) / e; }},                // Gonthier 2004
  };
  for (const Form& f : forms) {
    for (double e : {0.1, 0.3, 0.5, 0.7, 0.9, 0.95, 0.99}) {
      const NormalLaw law = MakeNormalLaw(f.law, SteelPair(e), RigGeometry());
      const double factor = std::visit(
          [](const auto& l) {
            if constexpr (requires { l.hysteresis; }) {
              return l.hysteresis.damping_factor;
            } else {
              return -1.0;
            }
          },
          law);
      EXPECT_NEAR(factor, f.factor(e), 1e-14 * f.factor(e)) << f.law << " e " << e;
      const double exact = ExactHysteresisRestitution(f.factor(e));
      for (double mass : {0.3, 2.0}) {
        for (double v0 : {0.05, 1.5}) {
          EXPECT_NEAR(SimulateImpact(law, mass, v0).achieved_restitution, exact, 1e-7)
              << f.law << " e " << e << " m " << mass << " v0 " << v0;
        }
      }
      const std::string name = f.law;
      if (name == "hunt-crossley") {
        EXPECT_NEAR(exact, e, 1.2 * (1.0 - e) * (1.0 - e)) << e;
      }
      if (name == "gonthier" && e <= 0.3) {
        EXPECT_NEAR(exact, e, 0.005) << e;
      }
      if (name == "gonthier" && e >= 0.9) {
        EXPECT_NEAR(1.0 - exact, 4.0 / 3.0 * (1.0 - e), 0.15 * (1.0 - e)) << e;
      }
    }
  }
}

TEST(ImpactReference, AchievedVersusInputRestitutionTable) {
  // Printed for the record (the lead quotes it); Hertz stiffness of the steel pair, 1 kg, 1 m/s
  // (the ratio depends on D̃ only). Known behaviour (Flores et al. 2011, Fig. 5 / Table 2;
  // Lankarani & Nikravesh 1990 derive their D̃ for cₑ → 1):
  //  * Flores follows the input over the whole range (here within 0.05);
  //  * Lankarani–Nikravesh is close only near 1 and badly overestimates low restitution;
  //  * elasto-plastic is exact by construction.
  const double inputs[] = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95, 0.99};
  const char* laws[] = {"lankarani-nikravesh", "hunt-crossley", "flores", "gonthier",
                        "elasto-plastic"};
  std::printf("\nachieved restitution of a single Hertz-type impact (n = 1.5)\n%8s", "input");
  for (const char* law : laws) std::printf(" %20s", law);
  std::printf("\n");
  for (double e : inputs) {
    std::printf("%8.2f", e);
    for (const char* name : laws) {
      const double achieved =
          SimulateImpact(MakeNormalLaw(name, SteelPair(e), RigGeometry()), 1.0, 1.0)
              .achieved_restitution;
      std::printf(" %20.4f", achieved);
      const std::string law = name;
      if (law == "flores") {
        EXPECT_NEAR(achieved, e, 0.05) << e;
      } else if (law == "elasto-plastic") {
        EXPECT_NEAR(achieved, e, 1e-9) << e;
      } else if (law == "lankarani-nikravesh") {
        if (e >= 0.9) {
          EXPECT_NEAR(achieved, e, 0.015) << e;
        }
        if (e >= 0.99) {
          EXPECT_NEAR(achieved, e, 2e-4) << e;
        }
        if (e <= 0.5) {
          EXPECT_GT(achieved - e, 0.2) << e;
        }
      }
      EXPECT_GE(achieved, 0.0);
      EXPECT_LE(achieved, 1.0);
    }
    std::printf("\n");
  }
}

}  // namespace
}  // namespace flexrod::contact
