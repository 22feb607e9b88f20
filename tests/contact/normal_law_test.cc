// tests/contact/normal_law_test.cc — properties every normal law must have: zero and
// non-tensile force, continuity at δ = 0, derivatives equal to central differences, monotone
// solved line laws with tiny residual, the state interfaces, no allocation in evaluation, and
// clear errors for bad input.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "contact/normal_law.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>

#include "common/error.h"
#include "tests/contact/contact_test_util.h"

// Counting global allocator: the evaluation hot path must not allocate (STYLE.md §17). GCC
// cannot see that this operator new pairs with the free() below.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
namespace {
std::atomic<long> g_allocations{0};
}  // namespace
void* operator new(std::size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace flexrod::contact {
namespace {

using testing::AllLaws;
using testing::kTypicalPenetration;
using testing::NeededOverrides;
using testing::RigGeometry;
using testing::SteelPair;

constexpr double kV0 = 1.0;  // approach velocity for the hysteresis family [m/s]

bool IsLineLaw(const NormalLaw& law) {
  return std::holds_alternative<Esdu78035Law>(law) || std::holds_alternative<JohnsonLaw>(law) ||
         std::holds_alternative<DubowskyFreudensteinLaw>(law);
}

TEST(NormalLaw, EveryNameBuildsTheLawOfThatName) {
  ASSERT_EQ(NormalLawNames().size(), std::variant_size_v<NormalLaw>);
  for (const auto& [name, law] : AllLaws()) {
    EXPECT_EQ(NormalLawName(law), name);
  }
}

TEST(NormalLaw, ForceIsZeroOutOfContactAndNeverTensile) {
  for (const auto& [name, law] : AllLaws(0.3)) {
    const LawState s = InitialLawState(law);
    for (double d : {-1e-3, -1e-9, 0.0}) {
      for (double r : {-10.0, -0.1, 0.0, 0.1, 10.0}) {
        EXPECT_EQ(CalcNormalForce(law, d, r, kV0, s).force, 0.0) << name << " delta " << d;
      }
    }
    for (double d : {1e-9, 1e-7, 1e-6, 1e-5, 1e-4}) {
      for (double r : {-100.0, -10.0, -1.0, -0.3, -0.01, 0.0, 0.01, 1.0, 10.0}) {
        const NormalForce f = CalcNormalForce(law, d, r, kV0, s);
        EXPECT_GE(f.force, 0.0) << name << " delta " << d << " rate " << r;
        if (f.force == 0.0) {
          EXPECT_EQ(f.d_penetration, 0.0) << name;
          EXPECT_EQ(f.d_rate, 0.0) << name;
        }
      }
    }
  }
}

TEST(NormalLaw, ForceIsContinuousAtZeroPenetration) {
  // F(ε) → 0 as ε → 0 for every law and any rate, except Kelvin–Voigt, whose force jumps by
  // exactly d·δ̇ while approaching (its known defect).
  for (const auto& [name, law] : AllLaws()) {
    const LawState s = InitialLawState(law);
    for (double r : {0.0, 0.5, 5.0}) {
      const double f_small = CalcNormalForce(law, 1e-15, r, kV0, s).force;
      const double f_smaller = CalcNormalForce(law, 1e-18, r, kV0, s).force;
      const double f_typical = CalcNormalForce(law, kTypicalPenetration, r, kV0, s).force;
      if (const auto* kv = std::get_if<KelvinVoigtLaw>(&law)) {
        EXPECT_NEAR(f_smaller, kv->damping * r, 1e-12 * kv->damping * r + 1e-6) << name;
        continue;
      }
      EXPECT_LT(f_small, 1e-6 * f_typical) << name << " rate " << r;
      EXPECT_LT(f_smaller, f_small + 1e-300) << name;
    }
  }
}

/// Central differences of F in δ, δ̇ and the differential state.
void CheckDerivatives(const std::string& name, const NormalLaw& law, double d, double r,
                      const LawState& s) {
  const NormalForce f = CalcNormalForce(law, d, r, kV0, s);
  ASSERT_GT(f.force, 0.0) << name;
  const double hd = 1e-6 * d;
  const double fd_d = (CalcNormalForce(law, d + hd, r, kV0, s).force -
                       CalcNormalForce(law, d - hd, r, kV0, s).force) /
                      (2.0 * hd);
  const double hr = 1e-6 * std::max(std::abs(r), 1.0);
  const double fd_r = (CalcNormalForce(law, d, r + hr, kV0, s).force -
                       CalcNormalForce(law, d, r - hr, kV0, s).force) /
                      (2.0 * hr);
  const double scale_d = std::abs(f.force / d);
  EXPECT_NEAR(f.d_penetration, fd_d, 1e-6 * scale_d) << name << " dF/ddelta at " << d;
  EXPECT_NEAR(f.d_rate, fd_r, 1e-6 * std::abs(f.force) / std::max(std::abs(r), 1.0))
      << name << " dF/drate at " << d << ", " << r;
  if (StateKind(law) == LawStateKind::kDifferential) {
    LawState sp = s, sm = s;
    sp[0] += hd;
    sm[0] -= hd;
    const double fd_s =
        (CalcNormalForce(law, d, r, kV0, sp).force - CalcNormalForce(law, d, r, kV0, sm).force) /
        (2.0 * hd);
    EXPECT_NEAR(f.d_state, fd_s, 1e-6 * scale_d) << name << " dF/dstate";
    const LawStateRate rate = CalcLawStateRate(law, d, s);
    const double fd_rate_d =
        (CalcLawStateRate(law, d + hd, s).rate - CalcLawStateRate(law, d - hd, s).rate) / (2 * hd);
    const double fd_rate_s =
        (CalcLawStateRate(law, d, sp).rate - CalcLawStateRate(law, d, sm).rate) / (2 * hd);
    const double rate_scale = std::abs(rate.d_penetration) + 1e-300;
    EXPECT_NEAR(rate.d_penetration, fd_rate_d, 1e-6 * rate_scale) << name;
    EXPECT_NEAR(rate.d_state, fd_rate_s, 1e-6 * rate_scale) << name;
  } else {
    EXPECT_EQ(f.d_state, 0.0) << name;
  }
}

TEST(NormalLaw, DerivativesMatchCentralDifferences) {
  for (const auto& [name, law] : AllLaws()) {
    for (double d :
         {0.3 * kTypicalPenetration, 2.0 * kTypicalPenetration, 8.0 * kTypicalPenetration}) {
      for (double r : {0.7, -0.05}) {
        LawState s = InitialLawState(law);
        if (StateKind(law) == LawStateKind::kDifferential) s[0] = 0.25 * d;
        CheckDerivatives(name, law, d, r, s);
        if (std::holds_alternative<ElastoPlasticLaw>(law)) {
          // Unloading branch below a recorded maximum.
          LawState h = InitialLawState(law);
          UpdateLawHistory(law, 1.5 * d, &h);
          CheckDerivatives(name + " (unloading)", law, 0.9 * 1.5 * d, r, h);
        }
      }
    }
  }
}

TEST(NormalLaw, LineLawsAreSolvedToRelativeResidual1e12AndAreMonotone) {
  for (const auto& [name, law] : AllLaws()) {
    if (!IsLineLaw(law)) continue;
    const double limit = ValidPenetrationLimit(law);
    ASSERT_TRUE(std::isfinite(limit)) << name;
    double previous = 0.0;
    for (double d = 1e-12; d < limit; d *= 1.3) {
      const double f = CalcNormalForce(law, d, 0.0, kV0, {}).force;
      const double residual = LineLawPenetration(law, f) - d;
      EXPECT_LE(std::abs(residual), 1e-12 * d) << name << " at delta = " << d;
      EXPECT_GT(f, previous) << name << " at delta = " << d;
      previous = f;
    }
    // Near the branch limit (slow, linear Newton convergence) the residual still holds.
    for (double frac : {0.9, 0.999, 0.999999}) {
      const double d = frac * limit;
      const double f = CalcNormalForce(law, d, 0.0, kV0, {}).force;
      EXPECT_LE(std::abs(LineLawPenetration(law, f) - d), 1e-12 * d) << name << " " << frac;
    }
  }
}

TEST(NormalLaw, LineLawsContinueLinearlyAndMonotonicallyBeyondTheirBranchLimit) {
  for (const auto& [name, law] : AllLaws()) {
    if (!IsLineLaw(law)) continue;
    const double limit = ValidPenetrationLimit(law);
    // dδ/dF = 0 at the limit, so F_lim − F ∝ √(δ_lim − δ) just below it.
    const double below = CalcNormalForce(law, limit * (1 - 1e-14), 0.0, kV0, {}).force;
    const NormalForce at = CalcNormalForce(law, limit, 0.0, kV0, {});
    const NormalForce beyond = CalcNormalForce(law, 2.0 * limit, 0.0, kV0, {});
    EXPECT_NEAR(below, at.force, 1e-6 * at.force) << name;
    // Secant continuation: F(2δ_lim) = 2 F(δ_lim), slope F_lim/δ_lim.
    EXPECT_NEAR(beyond.force, 2.0 * at.force, 1e-12 * at.force) << name;
    EXPECT_NEAR(beyond.d_penetration, at.force / limit, 1e-12 * at.force / limit) << name;
  }
}

TEST(NormalLaw, ElastoPlasticUnloadsToItsPermanentSet) {
  const NormalLaw law = MakeNormalLaw("elasto-plastic", SteelPair(0.6), RigGeometry());
  const auto& l = std::get<ElastoPlasticLaw>(law);
  LawState s = InitialLawState(law);
  const double dmax = 1e-5;
  UpdateLawHistory(law, 0.5 * dmax, &s);
  UpdateLawHistory(law, dmax, &s);
  UpdateLawHistory(law, 0.7 * dmax, &s);  // a smaller value does not lower the maximum
  EXPECT_EQ(s[0], dmax);
  EXPECT_DOUBLE_EQ(s[1], l.stiffness * std::pow(dmax, l.exponent));
  const double set = dmax * (1.0 - 0.36);  // δ_p = δ_max (1 − cₑ²)
  EXPECT_EQ(CalcNormalForce(law, set, -1.0, kV0, s).force, 0.0);
  EXPECT_GT(CalcNormalForce(law, set * (1 + 1e-6), -1.0, kV0, s).force, 0.0);
  EXPECT_DOUBLE_EQ(CalcNormalForce(law, dmax, -1.0, kV0, s).force, s[1]);
  EXPECT_EQ(NumLawStates(law), 2);
  EXPECT_EQ(StateKind(law), LawStateKind::kHistory);
}

TEST(NormalLaw, MaxwellDashpotStopsWhenTheSpringIsSlack) {
  const NormalLaw law =
      MakeNormalLaw("maxwell", SteelPair(), RigGeometry(), {{"effective-mass", 1.0}});
  EXPECT_EQ(NumLawStates(law), 1);
  LawState s{2e-6, 0.0};
  EXPECT_EQ(CalcNormalForce(law, 1e-6, 1.0, kV0, s).force, 0.0);  // δ < x_d: slack
  EXPECT_EQ(CalcLawStateRate(law, 1e-6, s).rate, 0.0);
  EXPECT_GT(CalcLawStateRate(law, 3e-6, s).rate, 0.0);
}

TEST(NormalLaw, HybridDampingIsLankaraniNikraveshDampingScaledByStiffnessRatio) {
  // Thesis eq. (29): C_mod = C_LN · k_ES / k_LN, with C_LN the Lankarani–Nikravesh damping
  // coefficient ∂F/∂δ̇ at the same δ, v₀, cₑ.
  const auto hybrid = MakeNormalLaw("hybrid", SteelPair(0.9), RigGeometry());
  const auto ln = MakeNormalLaw("lankarani-nikravesh", SteelPair(0.9), RigGeometry());
  const auto& h = std::get<HybridLaw>(hybrid);
  const double ratio = h.hysteresis.stiffness / h.lankarani_nikravesh_stiffness;
  for (double d : {1e-6, 5e-6}) {
    const double c_mod = CalcNormalForce(hybrid, d, 0.3, 0.8, {}).d_rate;
    const double c_ln = CalcNormalForce(ln, d, 0.3, 0.8, {}).d_rate;
    EXPECT_NEAR(c_mod, c_ln * ratio, 1e-12 * c_mod);
  }
  EXPECT_EQ(h.hysteresis.exponent, 1.5);
  EXPECT_GT(h.fit_r_squared, 0.9);  // thesis §3.3.4: "R² value greater than 0.9"
}

TEST(NormalLaw, ApproachVelocityIsFlooredForTheHysteresisFamily) {
  const auto law =
      MakeNormalLaw("flores", SteelPair(0.5), RigGeometry(), {{"min-approach-velocity", 0.01}});
  const double at_floor = CalcNormalForce(law, 1e-6, 0.005, 0.01, {}).force;
  EXPECT_EQ(CalcNormalForce(law, 1e-6, 0.005, 1e-9, {}).force, at_floor);
  EXPECT_EQ(CalcNormalForce(law, 1e-6, 0.005, 0.0, {}).force, at_floor);
}

TEST(NormalLaw, EvaluationDoesNotAllocate) {
  const auto laws = AllLaws();
  double sink = 0.0;
  const long before = g_allocations.load();
  for (const auto& [name, law] : laws) {
    LawState s = InitialLawState(law);
    for (double d : {1e-7, 1e-6, 1e-5}) {
      const NormalForce f = CalcNormalForce(law, d, 0.2, kV0, s);
      sink += f.force + f.d_penetration + CalcLawStateRate(law, d, s).rate;
      UpdateLawHistory(law, d, &s);
    }
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_GT(sink, 0.0);
}

TEST(NormalLaw, ResolvedParametersCarryUnitsAndSources) {
  const auto resolved = ResolveNormalLaw("hertz", SteelPair(), RigGeometry(), {{"exponent", 1.4}});
  bool saw_stiffness = false, saw_exponent = false;
  for (const auto& p : resolved.parameters) {
    if (p.name == "stiffness") {
      saw_stiffness = true;
      EXPECT_EQ(p.unit, "N/m^1.4");
      EXPECT_EQ(p.source, "derived");
    }
    if (p.name == "exponent") {
      saw_exponent = true;
      EXPECT_EQ(p.value, 1.4);
      EXPECT_EQ(p.source, "input");
    }
    EXPECT_FALSE(p.unit.empty()) << p.name;
  }
  EXPECT_TRUE(saw_stiffness && saw_exponent);
}

TEST(NormalLaw, OverridesReplaceDerivedValues) {
  const auto law = MakeNormalLaw("lankarani-nikravesh", SteelPair(), RigGeometry(),
                                 {{"stiffness", 1e9}, {"exponent", 1.2}, {"restitution", 0.7}});
  const auto& h = std::get<LankaraniNikraveshLaw>(law).hysteresis;
  EXPECT_EQ(h.stiffness, 1e9);
  EXPECT_EQ(h.exponent, 1.2);
  EXPECT_EQ(h.restitution, 0.7);
  EXPECT_DOUBLE_EQ(h.damping_factor, 0.75 * (1 - 0.49));
}

// ---- bad input ---------------------------------------------------------------------------------

template <typename F>
InputError CatchInputError(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError thrown";
  return InputError("", "", "");
}

TEST(NormalLawInput, UnknownLawNamesKeyAndValue) {
  const InputError e =
      CatchInputError([] { MakeNormalLaw("hertzian", SteelPair(), RigGeometry()); });
  EXPECT_EQ(e.key(), "contact.law");
  EXPECT_NE(e.value().find("hertzian"), std::string::npos);
  EXPECT_NE(e.rule().find("lankarani-nikravesh"), std::string::npos);
}

TEST(NormalLawInput, RestitutionOutsideZeroOneIsRejected) {
  for (double bad : {0.0, 1.5, -0.2}) {
    const InputError e = CatchInputError([&] {
      MakeNormalLaw("flores", SteelPair(), RigGeometry(), {{"restitution", bad}});
    });
    EXPECT_EQ(e.key(), "restitution");
    EXPECT_EQ(e.value(), FormatValue(bad));
    const InputError m =
        CatchInputError([&] { MakeNormalLaw("flores", SteelPair(bad), RigGeometry()); });
    EXPECT_EQ(m.key(), "contact.restitution");
  }
  EXPECT_NO_THROW(MakeNormalLaw("flores", SteelPair(1.0), RigGeometry()));
}

TEST(NormalLawInput, ParameterTheLawDoesNotTakeIsRejected) {
  const InputError e = CatchInputError([] {
    MakeNormalLaw("linear-spring", SteelPair(), RigGeometry(), {{"exponent", 2.0}});
  });
  EXPECT_EQ(e.key(), "exponent");
  EXPECT_EQ(e.value(), "2");
  EXPECT_NE(e.rule().find("does not take"), std::string::npos);
  EXPECT_NE(e.rule().find("linear-spring"), std::string::npos);
  const InputError f = CatchInputError([] {
    MakeNormalLaw("esdu-78035", SteelPair(), RigGeometry(), {{"restitution", 0.5}});
  });
  EXPECT_EQ(f.key(), "restitution");
}

TEST(NormalLawInput, BadGeometryAndMaterialsAreRejected) {
  ContactGeometry g = RigGeometry();
  g.pin_radius = g.bush_radius;  // zero clearance
  EXPECT_EQ(CatchInputError([&] { MakeNormalLaw("hertz", SteelPair(), g); }).key(),
            "contact.pin_radius");
  g.pin_radius = 1.1 * g.bush_radius;  // negative clearance
  EXPECT_EQ(CatchInputError([&] { MakeNormalLaw("hertz", SteelPair(), g); }).key(),
            "contact.pin_radius");
  ContactMaterials m = SteelPair();
  m.bush_poisson_ratio = 0.5;
  EXPECT_EQ(CatchInputError([&] { MakeNormalLaw("hertz", m, RigGeometry()); }).key(),
            "contact.bush_nu");
  EXPECT_EQ(CatchInputError([] {
              MakeNormalLaw("hertz", SteelPair(), RigGeometry(), {{"stiffness", -1.0}});
            }).key(),
            "stiffness");
}

TEST(NormalLawInput, DampingDerivationWithoutMassIsRejected) {
  const InputError e =
      CatchInputError([] { MakeNormalLaw("kelvin-voigt", SteelPair(), RigGeometry()); });
  EXPECT_EQ(e.key(), "effective-mass");
  EXPECT_NO_THROW(MakeNormalLaw("kelvin-voigt", SteelPair(), RigGeometry(), {{"damping", 100.0}}));
}

TEST(NormalLawInput, UnreachableStandardLinearSolidRestitutionIsRejected) {
  // With k₂ = k₁ the standard linear solid cannot dissipate more than about half the energy.
  const InputError e = CatchInputError([] {
    MakeNormalLaw("standard-linear-solid", SteelPair(0.2), RigGeometry(),
                  {{"effective-mass", 1.0}});
  });
  EXPECT_EQ(e.key(), "restitution");
}

TEST(NormalLawInput, PereiraFitOutsideItsClearanceRangeNeedsAnExponent) {
  const ContactGeometry wide{30e-3, 15e-3, 10e-3};  // 15 mm clearance
  EXPECT_EQ(CatchInputError([&] { MakeNormalLaw("pereira", SteelPair(), wide); }).key(),
            "contact.clearance");
  EXPECT_NO_THROW(MakeNormalLaw("pereira", SteelPair(), wide, {{"exponent", 1.1}}));
}

}  // namespace
}  // namespace flexrod::contact
