// tests/contact/normal_law_reftest.cc — absolute values of the normal laws pinned by
// independent calculations: Hertz's contact-radius solution, the h-convention form of the
// stiffness, 2-D elasticity (Flamant) for the line laws' log coefficient, the exact Lambert-W
// solution of the line laws, hand calculations in the Pereira fit's own units, and an
// independent parametric least-squares fit of ESDU-78035 for the hybrid.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gsl/gsl_sf_lambert.h>
#include <gtest/gtest.h>

#include <cmath>

#include "contact/normal_law.h"
#include "tests/contact/contact_test_util.h"
#include "tests/test_util.h"

namespace flexrod::contact {
namespace {

using testing::RigGeometry;
using testing::SteelPair;

using flexrod::test::kPi;

TEST(HertzReference, StiffnessMatchesTheContactRadiusSolution) {
  // Johnson 1985 eqs. 4.22–4.23: a³ = 3FR/(4E*), δ = a²/R, here with R = R* (internal).
  const NormalLaw law = MakeNormalLaw("hertz", SteelPair(), RigGeometry());
  const double e_star = 1.0 / (2.0 * (1.0 - 0.29 * 0.29) / 200e9);
  const ContactGeometry g = RigGeometry();
  const double r_star = 1.0 / (1.0 / g.pin_radius - 1.0 / g.bush_radius);  // curvatures subtract
  for (double force : {10.0, 1e3, 1e5}) {
    const double a = std::cbrt(3.0 * force * r_star / (4.0 * e_star));
    const double delta = a * a / r_star;
    EXPECT_NEAR(CalcNormalForce(law, delta, 0.0, 1.0, {}).force, force, 1e-12 * force);
  }
}

TEST(HertzReference, StiffnessAgreesWithTheHConventionForm) {
  // Lankarani & Nikravesh 1990 write K = 4/(3π(h_i + h_j))·√R* with h = (1 − ν²)/(πE):
  // the same number as (4/3)E*√R* — the π cancels only if each form uses its own convention.
  const ContactMaterials m{210e9, 0.3, 110e9, 0.34, 0.9};  // steel pin, bronze bush
  const ContactGeometry g = RigGeometry();
  const double h = (1 - 0.09) / (kPi * 210e9) + (1 - 0.34 * 0.34) / (kPi * 110e9);
  const double r_star = g.bush_radius * g.pin_radius / (g.bush_radius - g.pin_radius);
  const double k_h = 4.0 / (3.0 * kPi * h) * std::sqrt(r_star);
  EXPECT_NEAR(HertzStiffness(m, g), k_h, 1e-13 * k_h);
  // Hand value for the steel pair of the tests: E* = 1.0918222513374823e11 Pa,
  // R* = 0.17192625 m, K = 6.036174313252663e10 N/m^1.5 (python, double precision).
  EXPECT_NEAR(HertzStiffness(SteelPair(), g), 6.036174313252663e10, 1e3);
}

TEST(HertzReference, EveryHertzBasedLawHasTheHertzForceAtZeroRate) {
  // The hysteresis family, elasto-plastic (first loading) and ADAMS IMPACT share K and n with
  // Hertz; at δ̇ = 0 their force is the Hertz force, so the Hertz pin fixes their absolute value.
  const NormalLaw hertz = MakeNormalLaw("hertz", SteelPair(), RigGeometry());
  for (const char* name :
       {"lankarani-nikravesh", "hunt-crossley", "flores", "gonthier", "elasto-plastic", "impact"}) {
    const NormalLaw law =
        MakeNormalLaw(name, SteelPair(), RigGeometry(), testing::NeededOverrides(name));
    for (double d : {1e-7, 3e-6, 2e-5}) {
      const double f = CalcNormalForce(hertz, d, 0.0, 1.0, {}).force;
      EXPECT_NEAR(CalcNormalForce(law, d, 0.0, 1.0, InitialLawState(law)).force, f, 1e-12 * f)
          << name;
    }
  }
}

TEST(HertzReference, LinearStiffnessIsTheLeastSquaresFitOfHertz) {
  // k minimises ∫₀^δ_w (Kδ^1.5 − kδ)² dδ: k = 3∫Kδ^2.5 dδ/δ_w³, here by composite Simpson.
  const double w = 2e-5;
  const double k_hertz = HertzStiffness(SteelPair(), RigGeometry());
  const int n = 1000;
  double integral = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double d = w * i / n;
    integral += ((i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0)) * k_hertz * std::pow(d, 2.5);
  }
  integral *= w / (3.0 * n);
  const double k = 3.0 * integral / (w * w * w);
  const auto spring = std::get<LinearSpringLaw>(
      MakeNormalLaw("linear-spring", SteelPair(), RigGeometry(), {{"working-penetration", w}}));
  EXPECT_NEAR(spring.stiffness, k, 1e-8 * k);
  // Kelvin–Voigt and Maxwell use it; the standard linear solid splits it, k₁ = k₂ = k/2.
  const auto kv = std::get<KelvinVoigtLaw>(MakeNormalLaw(
      "kelvin-voigt", SteelPair(), RigGeometry(), {{"working-penetration", w}, {"damping", 1.0}}));
  EXPECT_NEAR(kv.stiffness, k, 1e-8 * k);
  const auto sls = std::get<StandardLinearSolidLaw>(
      MakeNormalLaw("standard-linear-solid", SteelPair(), RigGeometry(),
                    {{"working-penetration", w}, {"damping", 1.0}}));
  EXPECT_NEAR(sls.stiffness + sls.arm_stiffness, k, 1e-8 * k);
}

TEST(LineLawReference, LogCoefficientIsTheFlamantElasticValue) {
  // For δ = aF[ln(b/F) + c₀], dδ/dF = a[ln(b/F) + c₀ − 1], so the change of dδ/dF between two
  // forces is a·ln(F₂/F₁). 2-D elasticity fixes a = Σ(1 − ν²)/(πE)/L (Flamant line load;
  // Johnson 1985 §2.2): computed here from E, ν directly, not through the library.
  const ContactMaterials m{200e9, 0.29, 97e9, 0.31, 0.9};  // steel pin in a brass bush
  const ContactGeometry g = RigGeometry();
  const double a_elastic =
      ((1 - 0.29 * 0.29) / (kPi * 200e9) + (1 - 0.31 * 0.31) / (kPi * 97e9)) / g.length;
  for (const char* name : {"esdu-78035", "johnson", "dubowsky-freudenstein"}) {
    const NormalLaw law = MakeNormalLaw(name, m, g);
    const NormalForce f1 = CalcNormalForce(law, 1e-6, 0.0, 1.0, {});
    const NormalForce f2 = CalcNormalForce(law, 5e-6, 0.0, 1.0, {});
    const double a_measured =
        (1.0 / f1.d_penetration - 1.0 / f2.d_penetration) / std::log(f2.force / f1.force);
    EXPECT_NEAR(a_measured, a_elastic, 1e-9 * a_elastic) << name;
  }
}

TEST(LineLawReference, EsduAndJohnsonDifferOnlyByTheirDatumConstant) {
  // With the h convention both laws share a and b; δ_ESDU − δ_Johnson = 2FΣh/L exactly.
  const NormalLaw esdu = MakeNormalLaw("esdu-78035", SteelPair(), RigGeometry());
  const NormalLaw johnson = MakeNormalLaw("johnson", SteelPair(), RigGeometry());
  const double sum_h = 2.0 * (1 - 0.29 * 0.29) / (kPi * 200e9);
  for (double force : {1.0, 100.0, 1e4}) {
    EXPECT_NEAR(LineLawPenetration(esdu, force) - LineLawPenetration(johnson, force),
                2.0 * force * sum_h / RigGeometry().length,
                1e-12 * LineLawPenetration(esdu, force));
  }
}

TEST(LineLawReference, HandCalculatedPenetrationsAt1kN) {
  // Steel pair, L = 12.7 mm, ΔR = 0.5 mm, R_b = 9.525 mm, R_p = 9.025 mm, F = 1000 N,
  // Σh = 2(1 − 0.29²)/(π·200 GPa); values from the formulas in normal_law.h evaluated in python:
  //   ESDU-78035            δ = FΣh/L [ln(4LΔR/(FΣh)) + 1]             = 2.312233167571949e-06 m
  //   Johnson               δ = FΣh/L [ln(4LΔR/(FΣh)) − 1]             = 1.853115018350321e-06 m
  //   Dubowsky–Freudenstein δ = FΣh/L [ln(L³ΔR/(F R_b R_p Σh)) + 1]    = 2.1384549281042743e-06 m
  struct Case {
    const char* name;
    double delta;
  };
  for (const Case& c :
       {Case{"esdu-78035", 2.312233167571949e-06}, Case{"johnson", 1.853115018350321e-06},
        Case{"dubowsky-freudenstein", 2.1384549281042743e-06}}) {
    const NormalLaw law = MakeNormalLaw(c.name, SteelPair(), RigGeometry());
    EXPECT_NEAR(LineLawPenetration(law, 1000.0), c.delta, 1e-13 * c.delta) << c.name;
    EXPECT_NEAR(CalcNormalForce(law, c.delta, 0.0, 1.0, {}).force, 1000.0, 1e-9) << c.name;
  }
}

TEST(LineLawReference, SolvedForceEqualsTheExactLambertWSolution) {
  // x(c₀ − ln x) = δ/(ab), x = F/b, has the closed form x = exp(c₀ + W₋₁(−δ/(ab)·e^(−c₀)))
  // on the monotone branch (W₋₁ the lower real branch of Lambert W; GSL).
  for (const char* name : {"esdu-78035", "johnson", "dubowsky-freudenstein"}) {
    const NormalLaw law = MakeNormalLaw(name, SteelPair(), RigGeometry());
    const LogLineCurve* c = nullptr;
    if (auto* l = std::get_if<Esdu78035Law>(&law)) c = &l->curve;
    if (auto* l = std::get_if<JohnsonLaw>(&law)) c = &l->curve;
    if (auto* l = std::get_if<DubowskyFreudensteinLaw>(&law)) c = &l->curve;
    ASSERT_NE(c, nullptr);
    for (double d : {1e-10, 1e-8, 1e-6, 1e-5, 1e-4}) {
      const double arg = -d / (c->coefficient * c->force_scale) * std::exp(-c->constant);
      const double exact = c->force_scale * std::exp(c->constant + gsl_sf_lambert_Wm1(arg));
      EXPECT_NEAR(CalcNormalForce(law, d, 0.0, 1.0, {}).force, exact, 1e-10 * exact)
          << name << " at " << d;
    }
  }
}

TEST(LineLawReference, SmallPenetrationAsymptoticsHold) {
  // As δ → 0: F ≈ δ/(a L₁), L₁ = ln(b/F) + c₀ → ∞ (leading term of the inversion); the relative
  // error of the one-term form F₁ = δ/(a(ln(b a/δ) + c₀)) decays like ln(L₁)/L₁.
  const NormalLaw law = MakeNormalLaw("esdu-78035", SteelPair(), RigGeometry());
  const auto& c = std::get<Esdu78035Law>(law).curve;
  double previous_error = 1.0;
  for (double d : {1e-8, 1e-12, 1e-16, 1e-20}) {
    const double f = CalcNormalForce(law, d, 0.0, 1.0, {}).force;
    const double l1 = std::log(c.force_scale * c.coefficient / d) + c.constant;
    const double f1 = d / (c.coefficient * l1);
    const double error = std::abs(f / f1 - 1.0);
    EXPECT_LT(error, 1.5 * std::log(l1) / l1) << d;
    EXPECT_LT(error, previous_error) << d;
    previous_error = error;
  }
}

TEST(PereiraReference, HandCalculatedStiffnessAndExponentInFitUnits) {
  // Pereira et al. 2011 internal contact, fit units mm, N, N/mm²; hand calculation (python):
  // steel pair E* = 109182.22513374823 N/mm², L = 12.7 mm.
  //   ΔR = 0.5 mm (0.34954 < ΔR ≤ 10): Y = 0.0151·0.5 + 1.151 = 1.15855,
  //     n = Y·0.5^(−0.005) = 1.1625721942356844, K = (0.965·0.5 + 0.0965)·12.7·E*/0.5
  //     = 1605699.3121519815 N/mm^n; F(δ = 0.005 mm) = 3392.741180939551 N.
  //   ΔR = 0.2 mm (0.005 ≤ ΔR ≤ 0.34954): Y = 1.51 (ln 200)^(−0.151).
  const double e_star_mm = 109182.22513374823;
  {
    const NormalLaw law = MakeNormalLaw("pereira", SteelPair(), RigGeometry());
    const auto& h = std::get<PereiraLaw>(law).hysteresis;
    EXPECT_NEAR(h.exponent, 1.1625721942356844, 1e-14);
    EXPECT_NEAR(h.stiffness, 1605699.3121519815 * std::pow(1000.0, h.exponent), 1e-9 * h.stiffness);
    EXPECT_NEAR(CalcNormalForce(law, 5e-6, 0.0, 1.0, {}).force, 3392.741180939551, 1e-8);
  }
  {
    const ContactGeometry g{9.525e-3, 9.325e-3, 12.7e-3};
    const NormalLaw law = MakeNormalLaw("pereira", SteelPair(), g);
    const auto& h = std::get<PereiraLaw>(law).hysteresis;
    const double y = 1.51 * std::pow(std::log(200.0), -0.151);
    const double n = y * std::pow(0.2, -0.005);
    const double k_mm = (0.965 * 0.2 + 0.0965) * 12.7 * e_star_mm / 0.2;
    EXPECT_NEAR(h.exponent, n, 1e-12);
    // F in N for δ = 0.005 mm computed entirely in mm units.
    EXPECT_NEAR(CalcNormalForce(law, 5e-6, 0.0, 1.0, {}).force, k_mm * std::pow(0.005, n),
                1e-9 * k_mm * std::pow(0.005, n));
  }
}

TEST(HybridReference, StiffnessIsTheLeastSquaresFitOfEsduOverTheWorkingRange) {
  // Independent fit: parametrise the ESDU curve by F (explicit δ(F), no solver),
  // ∫₀^δ_w F δⁿ dδ = ∫₀^F_w F δ(F)ⁿ δ'(F) dF by composite Simpson in ln F, then
  // K = (2n+1) ∫ F δⁿ dδ / δ_w^(2n+1).
  for (double n : {1.0, 1.5}) {
    const double w = 8e-6;
    const auto resolved = ResolveNormalLaw("hybrid", SteelPair(0.9), RigGeometry(),
                                           {{"exponent", n}, {"working-penetration", w}});
    const auto& hybrid = std::get<HybridLaw>(resolved.law);
    const double sum_h = 2.0 * (1 - 0.29 * 0.29) / (kPi * 200e9);
    const double L = 12.7e-3, dr = 0.5e-3;
    const double a = sum_h / L, b = 4.0 * L * dr / sum_h;
    auto delta = [&](double f) { return a * f * (std::log(b / f) + 1.0); };
    auto ddelta = [&](double f) { return a * std::log(b / f); };
    double lo = 1e-30, hi = b;  // F_w by bisection on the explicit, increasing δ(F)
    for (int i = 0; i < 200; ++i) {
      const double mid = std::sqrt(lo * hi);
      (delta(mid) < w ? lo : hi) = mid;
    }
    const double f_w = hi;
    const int steps = 20000;  // in u = ln F from ln(F_w) − 60 (negligible tail) to ln F_w
    const double u0 = std::log(f_w) - 60.0, du = 60.0 / steps;
    double integral = 0.0;
    for (int i = 0; i <= steps; ++i) {
      const double f = std::exp(u0 + i * du);
      const double wgt = (i == 0 || i == steps) ? 1.0 : (i % 2 ? 4.0 : 2.0);
      integral += wgt * f * std::pow(delta(f), n) * ddelta(f) * f;  // dF = F du
    }
    integral *= du / 3.0;
    const double k = (2.0 * n + 1.0) * integral / std::pow(w, 2.0 * n + 1.0);
    EXPECT_NEAR(hybrid.hysteresis.stiffness, k, 1e-7 * k) << "n = " << n;
    EXPECT_GT(hybrid.fit_r_squared, 0.9) << "n = " << n;
  }
}

}  // namespace
}  // namespace flexrod::contact
