// contact/normal_law.cc — normal contact laws: names, evaluation, materials and geometry
// (parameter resolution: contact/normal_law_resolve.cc; see normal_law.h for formulas,
// conventions and sources).
// SPDX-License-Identifier: GPL-3.0-or-later
#include "contact/normal_law.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "common/error.h"
#include "contact/normal_law_detail.h"

namespace flexrod::contact {
namespace normal_law_detail {

// ---- names and accepted keys ----------------------------------------------------------------

const std::vector<LawSpec>& LawSpecs() {
  // Order = variant order (checked by a static_assert-like runtime test in the unit tests).
  static const std::vector<LawSpec> specs = {
      {"linear-spring", {"stiffness", "working-penetration"}},
      {"kelvin-voigt",
       {"stiffness", "damping", "restitution", "effective-mass", "working-penetration"}},
      {"maxwell", {"stiffness", "damping", "restitution", "effective-mass", "working-penetration"}},
      {"standard-linear-solid",
       {"stiffness", "stiffness-2", "damping", "restitution", "effective-mass",
        "working-penetration"}},
      {"hertz", {"stiffness", "exponent"}},
      {"lankarani-nikravesh", {"stiffness", "exponent", "restitution", "min-approach-velocity"}},
      {"hunt-crossley", {"stiffness", "exponent", "restitution", "min-approach-velocity"}},
      {"flores", {"stiffness", "exponent", "restitution", "min-approach-velocity"}},
      {"gonthier", {"stiffness", "exponent", "restitution", "min-approach-velocity"}},
      {"impact",
       {"stiffness", "exponent", "max-damping", "damping-penetration", "restitution",
        "effective-mass", "calibration-velocity"}},
      {"esdu-78035", {"compliance"}},
      {"johnson", {"compliance"}},
      {"dubowsky-freudenstein", {"compliance"}},
      {"pereira", {"stiffness", "exponent", "restitution", "min-approach-velocity"}},
      {"elasto-plastic", {"stiffness", "exponent", "restitution"}},
      {"hybrid",
       {"stiffness", "exponent", "restitution", "working-penetration", "min-approach-velocity"}},
  };
  return specs;
}

std::string JoinNames(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

const LawSpec& FindSpec(std::string_view name) {
  for (const LawSpec& s : LawSpecs()) {
    if (name == s.name) return s;
  }
  throw InputError("contact.law", "\"" + std::string(name) + "\"",
                   "unknown normal contact law; must be one of: " + JoinNames(NormalLawNames()));
}

std::string StiffnessUnit(double exponent) {
  return exponent == 1.0 ? std::string("N/m") : "N/m^" + FormatValue(exponent);
}

// ---- line-contact log curves ----------------------------------------------------------------

double CurvePenetration(const LogLineCurve& c, double force) {
  if (!(force > 0.0)) return 0.0;
  return c.coefficient * force * (std::log(c.force_scale / force) + c.constant);
}
double CurveLimitForce(const LogLineCurve& c) { return c.force_scale * std::exp(c.constant - 1.0); }
double CurveLimitPenetration(const LogLineCurve& c) { return c.coefficient * CurveLimitForce(c); }

/// Solves a F [ln(b/F) + c₀] = δ on the monotone branch by safeguarded Newton in y = ln(F/b).
/// ψ(y) = y + ln(c₀ − y) − ln(δ/(ab)) is increasing (ψ' = 1 − 1/(c₀ − y) > 0 for y < c₀ − 1) and
/// concave (ψ'' < 0), so from any start the first Newton iterate lies left of the root and the
/// iterates then increase monotonically to it: convergence is guaranteed without a bracket
/// (quadratic away from the branch limit, linear at it). The step is kept inside the branch.
void SolveCurve(const LogLineCurve& c, double penetration, double* force, double* slope) {
  const double a = c.coefficient, b = c.force_scale, c0 = c.constant;
  const double limit_penetration = CurveLimitPenetration(c);
  if (penetration >= limit_penetration) {
    // Beyond the elastic branch: continue with the secant slope F_lim/δ_lim = 1/a.
    *force = CurveLimitForce(c) + (penetration - limit_penetration) / a;
    *slope = 1.0 / a;
    return;
  }
  const double log_target = std::log(penetration / (a * b));
  const double y_limit = c0 - 1.0;
  // Start: one fixed-point step of x = δ̂/(c₀ − ln x) from x = δ̂.
  double y = log_target - std::log(std::max(c0 - log_target, 1.5));
  if (!(y < y_limit)) y = y_limit - 0.5;
  for (int iter = 0; iter < 400; ++iter) {
    const double u = c0 - y;  // > 1 on the branch
    const double psi = y + std::log(u) - log_target;
    if (psi == 0.0) break;
    const double dpsi = 1.0 - 1.0 / u;
    double y_new = y - psi / dpsi;
    if (!(y_new < y_limit)) y_new = 0.5 * (y + y_limit);
    const double dy = y_new - y;
    y = y_new;
    if (std::abs(dy) <= 2e-15 * std::max(1.0, std::abs(y))) break;
  }
  *force = b * std::exp(y);
  const double u = c0 - y;
  *slope = 1.0 / (a * (u - 1.0));
}

LogLineCurve EsduCurve(double compliance, double length, double clearance) {
  return {compliance / length, 4.0 * length * clearance / compliance, 1.0};
}
LogLineCurve JohnsonCurve(double compliance, double length, double clearance) {
  return {compliance / length, 4.0 * length * clearance / compliance, -1.0};
}
LogLineCurve DubowskyFreudensteinCurve(double compliance, double length, double clearance,
                                       double bush_radius, double pin_radius) {
  return {compliance / length,
          length * length * length * clearance / (bush_radius * pin_radius * compliance), 1.0};
}

}  // namespace normal_law_detail

using normal_law_detail::CurveLimitPenetration;
using normal_law_detail::CurvePenetration;
using normal_law_detail::FindSpec;
using normal_law_detail::kInf;
using normal_law_detail::LawSpec;
using normal_law_detail::LawSpecs;
using normal_law_detail::SolveCurve;

namespace {

// ---- evaluation per law ---------------------------------------------------------------------

NormalForce Clip(NormalForce f) { return f.force > 0.0 ? f : NormalForce{}; }

NormalForce Eval(const LinearSpringLaw& l, double d, double, double, const LawState&) {
  return {l.stiffness * d, l.stiffness, 0.0, 0.0};
}
NormalForce Eval(const KelvinVoigtLaw& l, double d, double r, double, const LawState&) {
  return Clip({l.stiffness * d + l.damping * r, l.stiffness, l.damping, 0.0});
}
NormalForce Eval(const MaxwellLaw& l, double d, double, double, const LawState& s) {
  return Clip({l.stiffness * (d - s[0]), l.stiffness, 0.0, -l.stiffness});
}
NormalForce Eval(const StandardLinearSolidLaw& l, double d, double, double, const LawState& s) {
  return Clip({l.stiffness * d + l.arm_stiffness * (d - s[0]), l.stiffness + l.arm_stiffness, 0.0,
               -l.arm_stiffness});
}
NormalForce Eval(const HertzLaw& l, double d, double, double, const LawState&) {
  const double p = PenetrationPower(d, l.exponent - 1.0);
  return {l.stiffness * p * d, l.exponent * l.stiffness * p, 0.0, 0.0};
}
NormalForce EvalHysteresis(const HysteresisParameters& h, double d, double r, double v0) {
  const double v = std::max(v0, h.min_approach_velocity);
  const double p = PenetrationPower(d, h.exponent - 1.0);
  const double elastic = h.stiffness * p * d;
  const double factor = 1.0 + h.damping_factor * r / v;
  return Clip({elastic * factor, h.exponent * h.stiffness * p * factor,
               elastic * h.damping_factor / v, 0.0});
}
NormalForce Eval(const ImpactFunctionLaw& l, double d, double r, double, const LawState&) {
  const double p = PenetrationPower(d, l.exponent - 1.0);
  const double x = std::min(d / l.damping_penetration, 1.0);
  const double c = l.max_damping * x * x * (3.0 - 2.0 * x);
  const double dc =
      d < l.damping_penetration ? l.max_damping * 6.0 * x * (1.0 - x) / l.damping_penetration : 0.0;
  return Clip({l.stiffness * p * d + c * r, l.exponent * l.stiffness * p + dc * r, c, 0.0});
}
NormalForce EvalCurve(const LogLineCurve& c, double d) {
  NormalForce f;
  SolveCurve(c, d, &f.force, &f.d_penetration);
  return f;
}
NormalForce Eval(const Esdu78035Law& l, double d, double, double, const LawState&) {
  return EvalCurve(l.curve, d);
}
NormalForce Eval(const JohnsonLaw& l, double d, double, double, const LawState&) {
  return EvalCurve(l.curve, d);
}
NormalForce Eval(const DubowskyFreudensteinLaw& l, double d, double, double, const LawState&) {
  return EvalCurve(l.curve, d);
}
NormalForce Eval(const ElastoPlasticLaw& l, double d, double, double, const LawState& s) {
  const double max_penetration = s[0], max_force = s[1];
  if (d >= max_penetration) {  // virgin loading curve
    const double p = PenetrationPower(d, l.exponent - 1.0);
    return {l.stiffness * p * d, l.exponent * l.stiffness * p, 0.0, 0.0};
  }
  const double set = max_penetration * (1.0 - l.restitution * l.restitution);  // δ_p
  if (d <= set) return {};
  const double span = max_penetration - set;
  const double ratio = (d - set) / span;
  const double p = PenetrationPower(ratio, l.exponent - 1.0);
  return {max_force * p * ratio, max_force * l.exponent * p / span, 0.0, 0.0};
}
template <typename Law>
requires requires(const Law& l) { l.hysteresis; }
NormalForce Eval(const Law& l, double d, double r, double v0, const LawState&) {
  return EvalHysteresis(l.hysteresis, d, r, v0);
}

}  // namespace

// ---- public -------------------------------------------------------------------------------

void ContactMaterials::Validate() const {
  auto modulus = [](const char* key, double v) {
    if (!(std::isfinite(v) && v > 0.0)) {
      throw InputError(key, FormatValue(v) + " Pa", "must be finite and > 0");
    }
  };
  auto poisson = [](const char* key, double v) {
    if (!(std::isfinite(v) && v > -1.0 && v < 0.5)) {
      throw InputError(key, FormatValue(v), "Poisson ratio must lie in (-1, 0.5)");
    }
  };
  modulus("contact.pin_E", pin_youngs_modulus);
  poisson("contact.pin_nu", pin_poisson_ratio);
  modulus("contact.bush_E", bush_youngs_modulus);
  poisson("contact.bush_nu", bush_poisson_ratio);
  if (!(std::isfinite(restitution) && restitution > 0.0 && restitution <= 1.0)) {
    throw InputError("contact.restitution", FormatValue(restitution),
                     "coefficient of restitution must lie in (0, 1]");
  }
}

double MaterialCompliance(double youngs_modulus, double poisson_ratio) {
  return (1.0 - poisson_ratio * poisson_ratio) / youngs_modulus;
}
double EffectiveModulus(const ContactMaterials& m) {
  return 1.0 / (MaterialCompliance(m.pin_youngs_modulus, m.pin_poisson_ratio) +
                MaterialCompliance(m.bush_youngs_modulus, m.bush_poisson_ratio));
}
double PiCompliance(const ContactMaterials& m) {
  return 1.0 / (std::numbers::pi * EffectiveModulus(m));
}
double InternalContactRadius(const ContactGeometry& g) {
  return g.bush_radius * g.pin_radius / (g.bush_radius - g.pin_radius);
}
double HertzStiffness(const ContactMaterials& m, const ContactGeometry& g) {
  return 4.0 / 3.0 * EffectiveModulus(m) * std::sqrt(InternalContactRadius(g));
}

const std::vector<std::string>& NormalLawNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v;
    for (const LawSpec& s : LawSpecs()) v.emplace_back(s.name);
    return v;
  }();
  return names;
}

std::string_view NormalLawName(const NormalLaw& law) { return LawSpecs()[law.index()].name; }

const std::vector<std::string>& NormalLawParameterKeys(std::string_view name) {
  return FindSpec(name).keys;
}

LawStateKind StateKind(const NormalLaw& law) {
  if (std::holds_alternative<MaxwellLaw>(law) ||
      std::holds_alternative<StandardLinearSolidLaw>(law)) {
    return LawStateKind::kDifferential;
  }
  if (std::holds_alternative<ElastoPlasticLaw>(law)) return LawStateKind::kHistory;
  return LawStateKind::kNone;
}

int NumLawStates(const NormalLaw& law) {
  switch (StateKind(law)) {
    case LawStateKind::kNone:
      return 0;
    case LawStateKind::kDifferential:
      return 1;
    case LawStateKind::kHistory:
      return 2;
  }
  return 0;
}

LawState InitialLawState(const NormalLaw&) { return LawState{0.0, 0.0}; }

NormalForce CalcNormalForce(const NormalLaw& law, double penetration, double rate,
                            double approach_velocity, const LawState& state) {
  if (!(penetration > 0.0)) return {};
  return std::visit(
      [&](const auto& l) { return Eval(l, penetration, rate, approach_velocity, state); }, law);
}

LawStateRate CalcLawStateRate(const NormalLaw& law, double penetration, const LawState& state) {
  if (const auto* m = std::get_if<MaxwellLaw>(&law)) {
    if (std::isinf(m->damping)) return {};
    const double stretch = penetration - state[0];
    if (!(penetration > 0.0) || !(stretch > 0.0)) return {};  // slack spring: dashpot at rest
    const double g = m->stiffness / m->damping;
    return {g * stretch, g, -g};
  }
  if (const auto* s = std::get_if<StandardLinearSolidLaw>(&law)) {
    if (std::isinf(s->damping)) return {};
    const double g = s->arm_stiffness / s->damping;
    return {g * (penetration - state[0]), g, -g};
  }
  return {};
}

void UpdateLawHistory(const NormalLaw& law, double penetration, LawState* state) {
  if (const auto* l = std::get_if<ElastoPlasticLaw>(&law)) {
    if (penetration > (*state)[0]) {
      (*state)[0] = penetration;
      (*state)[1] = l->stiffness * std::pow(penetration, l->exponent);
    }
  }
}

double LineLawPenetration(const NormalLaw& law, double force) {
  if (const auto* l = std::get_if<Esdu78035Law>(&law)) return CurvePenetration(l->curve, force);
  if (const auto* l = std::get_if<JohnsonLaw>(&law)) return CurvePenetration(l->curve, force);
  if (const auto* l = std::get_if<DubowskyFreudensteinLaw>(&law)) {
    return CurvePenetration(l->curve, force);
  }
  throw std::logic_error("LineLawPenetration: not a line-contact law");
}

double ValidPenetrationLimit(const NormalLaw& law) {
  if (const auto* l = std::get_if<Esdu78035Law>(&law)) return CurveLimitPenetration(l->curve);
  if (const auto* l = std::get_if<JohnsonLaw>(&law)) return CurveLimitPenetration(l->curve);
  if (const auto* l = std::get_if<DubowskyFreudensteinLaw>(&law)) {
    return CurveLimitPenetration(l->curve);
  }
  return kInf;
}

// Non-tensile Kelvin–Voigt oscillator: m ẍ = −(kx + dẋ) while kx + dẋ > 0, x(0) = 0, ẋ(0) = v₀.
// ζ < 1: x = (v₀/ω_d) e^(−αt) sin ω_d t, α = ζω_n = ω_n cos β, ω_d = ω_n sin β. The force ∝ −ẍ
// vanishes when tan ω_d t = 2αω_d/(α² − ω_d²) = tan 2β, first at ω_d t* = 2β, where
// ẋ = −v₀ e^(−αt*): cₑ = exp(−2βζ/√(1−ζ²)), β = arccos ζ. ζ > 1: the same with sinh/cosh,
// γt* = 2b, b = arccosh ζ, γ = ω_n sinh b: cₑ = exp(−2bζ/√(ζ²−1)). Both → e⁻² at ζ = 1.
double KelvinVoigtRestitution(double zeta) {
  FLEXROD_ASSERT(zeta >= 0.0);
  if (zeta == 0.0) return 1.0;
  if (std::abs(zeta - 1.0) < 1e-9) return std::exp(-2.0 * zeta);
  if (zeta < 1.0) return std::exp(-2.0 * zeta * std::acos(zeta) / std::sqrt(1.0 - zeta * zeta));
  return std::exp(-2.0 * zeta * std::acosh(zeta) / std::sqrt(zeta * zeta - 1.0));
}

double LinearOscillatorRestitution(double zeta) {
  FLEXROD_ASSERT(zeta >= 0.0);
  if (zeta >= 1.0) return 0.0;
  return std::exp(-std::numbers::pi * zeta / std::sqrt(1.0 - zeta * zeta));
}

}  // namespace flexrod::contact
