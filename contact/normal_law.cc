// contact/normal_law.cc — normal contact laws, one place per law: its name and keys, its
// evaluation, its parameters resolved from materials, geometry and overrides (the numerical
// calibrations they use: contact/normal_law_calibration.h; formulas, conventions and sources:
// normal_law.h).
// SPDX-License-Identifier: GPL-3.0-or-later
#include "contact/normal_law.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "common/error.h"
#include "contact/normal_law_calibration.h"

namespace flexrod::contact {
namespace {

using normal_law_calibration::CurveLimitPenetration;
using normal_law_calibration::CurvePenetration;
using normal_law_calibration::DubowskyFreudensteinCurve;
using normal_law_calibration::EsduCurve;
using normal_law_calibration::FitPowerLaw;
using normal_law_calibration::ImpactDamping;
using normal_law_calibration::JohnsonCurve;
using normal_law_calibration::KelvinVoigtDampingRatio;
using normal_law_calibration::LinearisedHertz;
using normal_law_calibration::MaxwellDampingRatio;
using normal_law_calibration::PowerFit;
using normal_law_calibration::SlsDamping;
using normal_law_calibration::SolveCurve;

constexpr double kInf = std::numeric_limits<double>::infinity();

/// A law's name and the parameter keys it accepts.
struct LawSpec {
  const char* name;
  std::vector<std::string> keys;
};

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
    if (!r.Has("working-penetration")) {  // the default: the clearance is what is too small
      throw InputError("clearance", FormatValue(g.clearance()) + " m",
                       "is too small for the ESDU-78035 law: its curve ends at 4*clearance = " +
                           FormatValue(CurveLimitPenetration(esdu)) +
                           " m, below the default working penetration " + FormatValue(w) +
                           " m; set a working penetration below that, or a larger clearance");
    }
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

// ---- public -------------------------------------------------------------------------------

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
