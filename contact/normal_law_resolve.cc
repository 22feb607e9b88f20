// contact/normal_law_resolve.cc — a normal law's parameters resolved from the contact's
// materials, geometry and the user's overrides (ResolveNormalLaw): damping from a restitution,
// power-law fits over the working range, each law's defaults with their sources recorded.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gsl/gsl_errno.h>
#include <gsl/gsl_integration.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "common/error.h"
#include "contact/impact.h"
#include "contact/normal_law.h"
#include "contact/normal_law_detail.h"

namespace flexrod::contact {
using normal_law_detail::CurveLimitPenetration;
using normal_law_detail::DubowskyFreudensteinCurve;
using normal_law_detail::EsduCurve;
using normal_law_detail::FindSpec;
using normal_law_detail::JohnsonCurve;
using normal_law_detail::JoinNames;
using normal_law_detail::kInf;
using normal_law_detail::LawSpec;
using normal_law_detail::SolveCurve;
using normal_law_detail::StiffnessUnit;

namespace {

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

/// The linear laws: a spring, alone or with a dashpot in parallel, in series, or both.
NormalLaw BuildLinearLaw(std::string_view name, Resolver& r, const Context& c) {
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
  throw std::logic_error("normal law table and builder disagree on " + std::string(name));
}

/// Hertz's K δⁿ, alone, with a hysteresis damping form, or elasto-plastic.
NormalLaw BuildHertzLaw(std::string_view name, Resolver& r, const Context& c) {
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
  if (name == "elasto-plastic") {
    auto [k, n] = HertzStiffnessExponent(r, c);
    return ElastoPlasticLaw{k, n, Restitution(r, c)};
  }
  throw std::logic_error("normal law table and builder disagree on " + std::string(name));
}

/// ADAMS IMPACT, its maximum damping calibrated to the restitution.
NormalLaw BuildImpactLaw(Resolver& r, const Context& c) {
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

/// The line-contact laws of a pin in a bush: log curves from the compliance.
NormalLaw BuildLineLaw(std::string_view name, Resolver& r, const Context& c) {
  const ContactGeometry& g = c.geometry;
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
  throw std::logic_error("normal law table and builder disagree on " + std::string(name));
}

/// Pereira, Ramalho, Ambrósio 2011, internal contact; fit units mm, N, N/mm².
NormalLaw BuildPereiraLaw(Resolver& r, const Context& c) {
  const ContactGeometry& g = c.geometry;
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

/// The thesis's hybrid law: the ESDU-78035 curve fitted by K δⁿ over the working
/// penetration, with Lankarani–Nikravesh damping.
NormalLaw BuildHybridLaw(Resolver& r, const Context& c) {
  const ContactGeometry& g = c.geometry;
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

NormalLaw Build(std::string_view name, Resolver& r, const Context& c) {
  if (name == "linear-spring" || name == "kelvin-voigt" || name == "maxwell" ||
      name == "standard-linear-solid")
    return BuildLinearLaw(name, r, c);
  if (name == "impact") return BuildImpactLaw(r, c);
  if (name == "esdu-78035" || name == "johnson" || name == "dubowsky-freudenstein")
    return BuildLineLaw(name, r, c);
  if (name == "pereira") return BuildPereiraLaw(r, c);
  if (name == "hybrid") return BuildHybridLaw(r, c);
  return BuildHertzLaw(name, r, c);
}

}  // namespace

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

}  // namespace flexrod::contact
