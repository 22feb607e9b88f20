// contact/normal_law.cc — normal contact laws: parameter resolution and evaluation
// (see normal_law.h for formulas, conventions and sources).
// SPDX-License-Identifier: GPL-3.0-or-later
#include "contact/normal_law.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_integration.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "common/error.h"
#include "contact/impact.h"

namespace flexrod::contact {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// ---- names and accepted keys ----------------------------------------------------------------

struct LawSpec {
  const char* name;
  std::vector<std::string> keys;
};

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

// ---- override validation ----------------------------------------------------------------------

void ValidateOverride(const std::string& key, double v) {
  const bool finite = std::isfinite(v);
  if (key == "restitution") {
    Require(finite && v > 0.0 && v <= 1.0, key, v, "coefficient of restitution must lie in (0, 1]");
  } else if (key == "exponent") {
    Require(finite && v >= 1.0 && v <= 10.0, key, v,
            "force exponent must lie in [1, 10] (n >= 1 keeps dF/ddelta finite at delta = 0)");
  } else if (key == "damping" || key == "max-damping") {
    Require(finite && v >= 0.0, key, v, "must be finite and >= 0 [N*s/m]");
  } else {
    // stiffness, stiffness-2, effective-mass, working-penetration, min-approach-velocity,
    // damping-penetration, compliance
    Require(finite && v > 0.0, key, v, "must be finite and > 0");
  }
}

/// Collects the resolved record while reading overrides with their defaults.
class Resolver {
 public:
  Resolver(const LawSpec& spec, const ParameterMap& overrides)
      : spec_(spec), overrides_(overrides) {
    for (const auto& [key, value] : overrides) {
      if (std::find(spec.keys.begin(), spec.keys.end(), key) == spec.keys.end()) {
        throw InputError(key, FormatValue(value),
                         std::string("law '") + spec.name +
                             "' does not take this parameter; it takes: " + JoinNames(spec.keys));
      }
      ValidateOverride(key, value);
    }
  }
  bool Has(const std::string& key) const { return overrides_.count(key) > 0; }
  /// The override if given, else `fallback` (recorded with `source`).
  template <typename Fallback>
  double Get(const std::string& key, const std::string& unit, Fallback&& fallback,
             const char* source = "derived") {
    auto it = overrides_.find(key);
    double v;
    const char* src;
    if (it != overrides_.end()) {
      v = it->second;
      src = "input";
    } else {
      v = fallback();
      src = source;
    }
    Record(key, v, unit, src);
    return v;
  }
  void Record(const std::string& name, double value, const std::string& unit, const char* source) {
    params_.push_back({name, value, unit, source});
  }
  /// Fixes the unit of an already-recorded entry (stiffness units depend on the exponent).
  void SetUnit(const std::string& name, const std::string& unit) {
    for (auto& p : params_) {
      if (p.name == name) p.unit = unit;
    }
  }
  std::vector<ResolvedParameter> Take() { return std::move(params_); }
  const char* law() const { return spec_.name; }

 private:
  const LawSpec& spec_;
  const ParameterMap& overrides_;
  std::vector<ResolvedParameter> params_;
};

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

// ---- damping from restitution ------------------------------------------------------------------

/// Inverse of KelvinVoigtRestitution by bisection on ζ (the function decreases monotonically
/// from 1 at ζ = 0 to 0 as ζ → ∞).
double KelvinVoigtDampingRatio(double restitution) {
  if (restitution >= 1.0) return 0.0;
  double lo = 0.0, hi = 1.0;
  while (KelvinVoigtRestitution(hi) > restitution) hi *= 2.0;
  for (int i = 0; i < 200 && hi - lo > 1e-15 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (KelvinVoigtRestitution(mid) > restitution ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

/// Maxwell: cₑ = exp(−πζ/√(1−ζ²)) ⇔ ζ = −ln cₑ/√(π² + ln²cₑ).
double MaxwellDampingRatio(double restitution) {
  const double l = std::log(restitution);
  return -l / std::sqrt(std::numbers::pi * std::numbers::pi + l * l);
}

double SlsRestitution(double k1, double k2, double damping, double mass) {
  ImpactOptions options;
  options.rel_tol = 1e-10;
  options.num_samples = 20;
  return SimulateImpact(StandardLinearSolidLaw{k1, k2, damping}, mass, 1.0, options)
      .achieved_restitution;
}

/// Standard linear solid: restitution tends to 1 both for d → 0 (spring k₁) and d → ∞ (spring
/// k₁ + k₂) and has one minimum in between. We locate the minimum (golden section in ln d) and
/// solve on the large-d branch (bisection in ln d); the relation is independent of v₀ (linear).
double SlsDamping(double k1, double k2, double mass, double restitution) {
  if (restitution >= 1.0) return kInf;
  const double scale = std::sqrt((k1 + k2) * mass);
  auto e_of = [&](double log_eta) {
    return SlsRestitution(k1, k2, scale * std::exp(log_eta), mass);
  };
  double a = std::log(1e-3), b = std::log(1e3);
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = b - g * (b - a), x2 = a + g * (b - a);
  double f1 = e_of(x1), f2 = e_of(x2);
  for (int i = 0; i < 40; ++i) {
    if (f1 < f2) {
      b = x2;
      x2 = x1;
      f2 = f1;
      x1 = b - g * (b - a);
      f1 = e_of(x1);
    } else {
      a = x1;
      x1 = x2;
      f1 = f2;
      x2 = a + g * (b - a);
      f2 = e_of(x2);
    }
  }
  const double log_eta_min = 0.5 * (a + b);
  const double e_min = e_of(log_eta_min);
  if (restitution < e_min) {
    throw InputError("restitution", FormatValue(restitution),
                     "standard-linear-solid with stiffness-2/stiffness = " + FormatValue(k2 / k1) +
                         " cannot reach a restitution below " + FormatValue(e_min) +
                         "; raise stiffness-2 or give the damping explicitly");
  }
  double lo = log_eta_min, hi = std::log(1e3);
  while (e_of(hi) < restitution) hi += std::log(10.0);
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (e_of(mid) < restitution ? lo : hi) = mid;
  }
  return scale * std::exp(0.5 * (lo + hi));
}

/// ADAMS IMPACT: restitution is not scale-invariant (d_max and c_max are absolute), so c_max is
/// calibrated for one impact of mass m at speed v: bisection in ln c_max on the decreasing
/// relation cₑ(c_max) (cₑ → 1 as c_max → 0; a mass held by the wall counts as cₑ = 0).
double ImpactDamping(double k, double n, double dmax, double mass, double speed,
                     double restitution) {
  if (restitution >= 1.0) return 0.0;
  ImpactOptions options;
  options.rel_tol = 1e-10;
  options.num_samples = 20;
  options.max_duration_factor = 100.0;
  auto e_of = [&](double log_c) {
    try {
      return SimulateImpact(ImpactFunctionLaw{k, n, std::exp(log_c), dmax}, mass, speed, options)
          .achieved_restitution;
    } catch (const NumericalError&) {
      return 0.0;
    }
  };
  // Critical damping of the spring linearised at the elastic peak penetration.
  const double peak = std::pow((n + 1.0) * mass * speed * speed / (2.0 * k), 1.0 / (n + 1.0));
  const double reference = 2.0 * std::sqrt(k * std::pow(peak, n - 1.0) * mass);
  double lo = std::log(reference * 1e-6), hi = std::log(reference);
  for (int i = 0; i < 40 && e_of(hi) > restitution; ++i) hi += std::log(10.0);
  for (int i = 0; i < 40 && e_of(lo) < restitution; ++i) lo -= std::log(10.0);
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (e_of(mid) > restitution ? lo : hi) = mid;
  }
  return std::exp(0.5 * (lo + hi));
}

// ---- power-law fits over the working range ----------------------------------------------------

/// Least-squares fit of F(δ) by Kδⁿ over [0, δ_w]: K = (2n+1)/δ_w^(2n+1) ∫₀^δ_w F δⁿ dδ; also R².
struct PowerFit {
  double stiffness;
  double r_squared;
};

template <typename Force>
PowerFit FitPowerLaw(Force&& force, double exponent, double working_penetration) {
  struct Ctx {
    Force* f;
    double n;
    int moment;  // 0: F, 1: F δⁿ, 2: F²
  };
  auto integrand = [](double x, void* p) -> double {
    auto* c = static_cast<Ctx*>(p);
    const double f = (*c->f)(x);
    if (c->moment == 0) return f;
    if (c->moment == 1) return f * std::pow(x, c->n);
    return f * f;
  };
  std::unique_ptr<gsl_integration_workspace, decltype(&gsl_integration_workspace_free)> ws(
      gsl_integration_workspace_alloc(200), &gsl_integration_workspace_free);
  gsl_error_handler_t* old = gsl_set_error_handler_off();
  double moments[3];
  for (int m = 0; m < 3; ++m) {
    Ctx ctx{&force, exponent, m};
    gsl_function fn{integrand, &ctx};
    double result = 0.0, err = 0.0;
    const int status = gsl_integration_qags(&fn, 0.0, working_penetration, 0.0, 1e-10, 200,
                                            ws.get(), &result, &err);
    if (status != GSL_SUCCESS && status != GSL_EROUND) {
      gsl_set_error_handler(old);
      throw NumericalError(
          std::string("power-law fit of the contact law: GSL quadrature failed: ") +
          gsl_strerror(status));
    }
    moments[m] = result;
  }
  gsl_set_error_handler(old);
  const double w = working_penetration;
  const double n = exponent;
  const double k = (2.0 * n + 1.0) * moments[1] / std::pow(w, 2.0 * n + 1.0);
  // ∫(F − Kδⁿ)² = ∫F² − 2K∫Fδⁿ + K² w^(2n+1)/(2n+1);  ∫(F − F̄)² = ∫F² − (∫F)²/w.
  const double ss_res =
      moments[2] - 2.0 * k * moments[1] + k * k * std::pow(w, 2.0 * n + 1.0) / (2.0 * n + 1.0);
  const double ss_tot = moments[2] - moments[0] * moments[0] / w;
  return {k, 1.0 - ss_res / ss_tot};
}

/// Hertz K δ^1.5 fitted by kδ over [0, δ_w]: k = 3K∫δ^2.5/δ_w³ = (6/7)K√δ_w.
double LinearisedHertz(double hertz_stiffness, double working_penetration) {
  return 6.0 / 7.0 * hertz_stiffness * std::sqrt(working_penetration);
}

// ---- resolution per law -------------------------------------------------------------------------

struct Context {
  const ContactMaterials& materials;
  const ContactGeometry& geometry;
  double effective_modulus;
  double internal_radius;
  double hertz_stiffness;
  double pi_compliance;
};

double Restitution(Resolver& r, const Context& c) {
  return r.Get(
      "restitution", "1", [&] { return c.materials.restitution; }, "input");
}

void RecordHertzBasis(Resolver& r, const Context& c) {
  r.Record("effective-modulus", c.effective_modulus, "Pa", "derived");
  r.Record("internal-radius", c.internal_radius, "m", "derived");
}

/// Stiffness and exponent of a Hertz-family law (K default (4/3)E*√R*, n default 1.5).
std::pair<double, double> HertzStiffnessExponent(Resolver& r, const Context& c) {
  RecordHertzBasis(r, c);
  const double k = r.Get("stiffness", "", [&] { return c.hertz_stiffness; });
  const double n = r.Get(
      "exponent", "1", [] { return 1.5; }, "default");
  r.SetUnit("stiffness", StiffnessUnit(n));
  return {k, n};
}

double LinearStiffness(Resolver& r, const Context& c, double fraction = 1.0) {
  RecordHertzBasis(r, c);
  const double w = r.Get(
      "working-penetration", "m", [] { return kDefaultWorkingPenetration; }, "default");
  return r.Get("stiffness", "N/m",
               [&] { return fraction * LinearisedHertz(c.hertz_stiffness, w); });
}

double EffectiveMass(Resolver& r, const char* law, const char* why, double restitution) {
  if (!r.Has("effective-mass")) {
    if (restitution >= 1.0) return 1.0;  // elastic: the damping (0 or +inf) does not depend on m
    throw InputError("effective-mass", "(not given)",
                     std::string("law '") + law + "' needs the effective mass [kg] " + why +
                         ", or an explicit damping");
  }
  return r.Get("effective-mass", "kg", [] { return 0.0; });
}

HysteresisParameters Hysteresis(Resolver& r, const Context& c, double stiffness, double exponent,
                                double (*factor)(double)) {
  const double e = Restitution(r, c);
  const double v = r.Get(
      "min-approach-velocity", "m/s", [] { return kDefaultMinApproachVelocity; }, "default");
  const double dtilde = factor(e);
  r.Record("damping-factor", dtilde, "1", "derived");
  return {stiffness, exponent, e, dtilde, v};
}

double LnFactor(double e) { return 0.75 * (1.0 - e * e); }
double HcFactor(double e) { return 1.5 * (1.0 - e); }
double FloresFactor(double e) { return 1.6 * (1.0 - e) / e; }
double GonthierFactor(double e) { return (1.0 - e * e) / e; }

double Compliance(Resolver& r, const Context& c) {
  r.Record("effective-modulus", c.effective_modulus, "Pa", "derived");
  r.Record("length", c.geometry.length, "m", "input");
  r.Record("clearance", c.geometry.clearance(), "m", "derived");
  return r.Get("compliance", "1/Pa", [&] { return c.pi_compliance; });
}

NormalLaw Build(std::string_view name, Resolver& r, const Context& c) {
  const ContactGeometry& g = c.geometry;
  if (name == "linear-spring") {
    return LinearSpringLaw{LinearStiffness(r, c)};
  }
  if (name == "kelvin-voigt") {
    const double k = LinearStiffness(r, c);
    const double e = Restitution(r, c);
    if (r.Has("damping")) return KelvinVoigtLaw{k, r.Get("damping", "N*s/m", [] { return 0.0; })};
    const double m =
        EffectiveMass(r, "kelvin-voigt", "to derive the damping from the restitution", e);
    const double zeta = KelvinVoigtDampingRatio(e);
    r.Record("damping-ratio", zeta, "1", "derived");
    return KelvinVoigtLaw{k,
                          r.Get("damping", "N*s/m", [&] { return 2.0 * zeta * std::sqrt(k * m); })};
  }
  if (name == "maxwell") {
    const double k = LinearStiffness(r, c);
    const double e = Restitution(r, c);
    if (r.Has("damping")) {
      const double d = r.Get("damping", "N*s/m", [] { return 0.0; });
      Require(d > 0.0, "damping", d, "maxwell needs a dashpot damping > 0 [N*s/m]");
      return MaxwellLaw{k, d};
    }
    const double m = EffectiveMass(r, "maxwell", "to derive the damping from the restitution", e);
    const double zeta = MaxwellDampingRatio(e);
    r.Record("damping-ratio", zeta, "1", "derived");
    return MaxwellLaw{k, r.Get("damping", "N*s/m", [&] {
                        return zeta > 0.0 ? std::sqrt(k * m) / (2.0 * zeta) : kInf;
                      })};
  }
  if (name == "standard-linear-solid") {
    const double k1 = LinearStiffness(r, c, 0.5);
    const double k2 = r.Get("stiffness-2", "N/m", [&] { return k1; });
    const double e = Restitution(r, c);
    if (r.Has("damping")) {
      const double d = r.Get("damping", "N*s/m", [] { return 0.0; });
      Require(d > 0.0, "damping", d, "standard-linear-solid needs a dashpot damping > 0 [N*s/m]");
      return StandardLinearSolidLaw{k1, k2, d};
    }
    const double m =
        EffectiveMass(r, "standard-linear-solid", "to calibrate the damping to the restitution", e);
    return StandardLinearSolidLaw{
        k1, k2, r.Get("damping", "N*s/m", [&] { return SlsDamping(k1, k2, m, e); })};
  }
  if (name == "hertz") {
    auto [k, n] = HertzStiffnessExponent(r, c);
    return HertzLaw{k, n};
  }
  if (name == "lankarani-nikravesh") {
    auto [k, n] = HertzStiffnessExponent(r, c);
    return LankaraniNikraveshLaw{Hysteresis(r, c, k, n, LnFactor)};
  }
  if (name == "hunt-crossley") {
    auto [k, n] = HertzStiffnessExponent(r, c);
    return HuntCrossleyLaw{Hysteresis(r, c, k, n, HcFactor)};
  }
  if (name == "flores") {
    auto [k, n] = HertzStiffnessExponent(r, c);
    return FloresLaw{Hysteresis(r, c, k, n, FloresFactor)};
  }
  if (name == "gonthier") {
    auto [k, n] = HertzStiffnessExponent(r, c);
    return GonthierLaw{Hysteresis(r, c, k, n, GonthierFactor)};
  }
  if (name == "impact") {
    // Named, not a structured binding: clang 14 (the fuzz build) refuses to capture one.
    const std::pair<double, double> kn = HertzStiffnessExponent(r, c);
    const double k = kn.first, n = kn.second;
    const double dmax = r.Get(
        "damping-penetration", "m", [] { return kDefaultImpactDampingPenetration; }, "default");
    const double e = Restitution(r, c);
    if (r.Has("max-damping")) {
      return ImpactFunctionLaw{k, n, r.Get("max-damping", "N*s/m", [] { return 0.0; }), dmax};
    }
    const double m = EffectiveMass(r, "impact", "to calibrate max-damping to the restitution", e);
    const double v = r.Get(
        "calibration-velocity", "m/s", [] { return kDefaultCalibrationVelocity; }, "default");
    const double cmax =
        r.Get("max-damping", "N*s/m", [&] { return ImpactDamping(k, n, dmax, m, v, e); });
    return ImpactFunctionLaw{k, n, cmax, dmax};
  }
  if (name == "esdu-78035") {
    const double h = Compliance(r, c);
    const LogLineCurve curve = EsduCurve(h, g.length, g.clearance());
    r.Record("branch-limit-penetration", CurveLimitPenetration(curve), "m", "derived");
    return Esdu78035Law{h, g.length, g.clearance(), curve};
  }
  if (name == "johnson") {
    const double h = Compliance(r, c);
    const LogLineCurve curve = JohnsonCurve(h, g.length, g.clearance());
    r.Record("branch-limit-penetration", CurveLimitPenetration(curve), "m", "derived");
    return JohnsonLaw{h, g.length, g.clearance(), curve};
  }
  if (name == "dubowsky-freudenstein") {
    const double h = Compliance(r, c);
    const LogLineCurve curve =
        DubowskyFreudensteinCurve(h, g.length, g.clearance(), g.bush_radius, g.pin_radius);
    r.Record("branch-limit-penetration", CurveLimitPenetration(curve), "m", "derived");
    return DubowskyFreudensteinLaw{h, g.length, g.clearance(), g.bush_radius, g.pin_radius, curve};
  }
  if (name == "pereira") {
    // Pereira, Ramalho, Ambrósio 2011, internal contact; fit units mm, N, N/mm².
    const double clearance_mm = g.clearance() * 1e3;
    const double length_mm = g.length * 1e3;
    const double modulus_nmm2 = c.effective_modulus * 1e-6;
    r.Record("effective-modulus", c.effective_modulus, "Pa", "derived");
    r.Record("clearance", g.clearance(), "m", "derived");
    const double n = r.Get("exponent", "1", [&] {
      double y;
      if (clearance_mm >= 0.005 && clearance_mm <= 0.34954) {
        y = 1.51 * std::pow(std::log(1000.0 * clearance_mm), -0.151);
      } else if (clearance_mm > 0.34954 && clearance_mm <= 10.0) {
        y = 0.0151 * clearance_mm + 1.151;
      } else {
        throw InputError("contact.clearance", FormatValue(clearance_mm) + " mm",
                         "the Pereira et al. (2011) exponent fit holds for 0.005 mm <= clearance "
                         "<= 10 mm; give the exponent explicitly");
      }
      return y * std::pow(clearance_mm, -0.005);
    });
    const double k = r.Get("stiffness", StiffnessUnit(n), [&] {
      const double k_mm = (0.965 * clearance_mm + 0.0965) * length_mm * modulus_nmm2 / clearance_mm;
      return k_mm * std::pow(1000.0, n);  // N/mm^n → N/m^n
    });
    return PereiraLaw{Hysteresis(r, c, k, n, LnFactor), g.clearance()};
  }
  if (name == "elasto-plastic") {
    auto [k, n] = HertzStiffnessExponent(r, c);
    return ElastoPlasticLaw{k, n, Restitution(r, c)};
  }
  if (name == "hybrid") {
    r.Record("effective-modulus", c.effective_modulus, "Pa", "derived");
    r.Record("internal-radius", c.internal_radius, "m", "derived");
    r.Record("lankarani-nikravesh-stiffness", c.hertz_stiffness, "N/m^1.5", "derived");
    const double n = r.Get(
        "exponent", "1", [] { return 1.5; }, "default");
    const double w = r.Get(
        "working-penetration", "m", [] { return kDefaultWorkingPenetration; }, "default");
    const LogLineCurve esdu = EsduCurve(c.pi_compliance, g.length, g.clearance());
    if (!(w < CurveLimitPenetration(esdu))) {
      throw InputError("working-penetration", FormatValue(w) + " m",
                       "must be below the ESDU-78035 branch limit 4*clearance = " +
                           FormatValue(CurveLimitPenetration(esdu)) + " m");
    }
    const PowerFit fit = FitPowerLaw(
        [&](double d) {
          double f, s;
          SolveCurve(esdu, d, &f, &s);
          return d > 0.0 ? f : 0.0;
        },
        n, w);
    r.Record("esdu-fit-r-squared", fit.r_squared, "1", "derived");
    const double k = r.Get("stiffness", StiffnessUnit(n), [&] { return fit.stiffness; });
    r.Record("damping-scale-k_es/k_ln", k / c.hertz_stiffness,
             n == 1.5 ? std::string("1") : "m^" + FormatValue(1.5 - n), "derived");
    return HybridLaw{Hysteresis(r, c, k, n, LnFactor), w, fit.r_squared, c.hertz_stiffness};
  }
  throw std::logic_error("normal law table and builder disagree on " + std::string(name));
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

ResolvedNormalLaw ResolveNormalLaw(std::string_view name, const ContactMaterials& materials,
                                   const ContactGeometry& geometry, const ParameterMap& overrides) {
  const LawSpec& spec = FindSpec(name);
  materials.Validate();
  geometry.Validate();
  Resolver resolver(spec, overrides);
  const Context context{materials,
                        geometry,
                        EffectiveModulus(materials),
                        InternalContactRadius(geometry),
                        HertzStiffness(materials, geometry),
                        PiCompliance(materials)};
  NormalLaw law = Build(name, resolver, context);
  FLEXROD_ASSERT(NormalLawName(law) == name);
  return {std::move(law), resolver.Take()};
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
