// contact/friction_law.cc — friction laws (see friction_law.h).
// SPDX-License-Identifier: GPL-3.0-or-later
#include "contact/friction_law.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"

namespace flexrod::contact {
namespace {

struct FrictionSpec {
  const char* name;
  std::vector<std::string> keys;
};

const std::vector<FrictionSpec>& Specs() {
  static const std::vector<FrictionSpec> specs = {
      {"coulomb", {"friction-coefficient", "stick-velocity", "slip-velocity"}},
      {"threlfall", {"friction-coefficient", "velocity-scale"}},
      {"stribeck",
       {"friction-coefficient", "static-coefficient", "stribeck-velocity", "stribeck-exponent",
        "viscous-coefficient", "regularisation-velocity"}},
      {"lugre",
       {"friction-coefficient", "static-coefficient", "stribeck-velocity", "bristle-stiffness",
        "bristle-damping", "viscous-coefficient"}},
  };
  return specs;
}

std::string Join(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : ", ") + s;
  return out;
}

double Sign(double v) { return v > 0.0 ? 1.0 : (v < 0.0 ? -1.0 : 0.0); }

class Reader {
 public:
  Reader(const FrictionSpec& spec, const ParameterMap& overrides) : overrides_(overrides) {
    for (const auto& [key, value] : overrides) {
      if (std::find(spec.keys.begin(), spec.keys.end(), key) == spec.keys.end()) {
        throw InputError(key, FormatValue(value),
                         std::string("friction law '") + spec.name +
                             "' does not take this parameter; it takes: " + Join(spec.keys));
      }
      if (key == "viscous-coefficient") {
        Require(std::isfinite(value) && value >= 0.0, key, value, "must be finite and >= 0");
      } else {
        Require(std::isfinite(value) && value > 0.0, key, value, "must be finite and > 0");
      }
    }
  }
  double Get(const std::string& key, double fallback, const char* unit) {
    auto it = overrides_.find(key);
    const bool given = it != overrides_.end();
    const double v = given ? it->second : fallback;
    params_.push_back({key, v, unit, given ? "input" : "default"});
    return v;
  }
  bool Has(const std::string& key) const { return overrides_.count(key) > 0; }
  std::vector<ResolvedParameter> Take() { return std::move(params_); }

 private:
  const ParameterMap& overrides_;
  std::vector<ResolvedParameter> params_;
};

/// μ(v) = μ_c + (μ_s − μ_c) exp(−(|v|/v_s)^i) and its derivative with respect to v.
void StribeckCurve(double mu_c, double mu_s, double vs, double i, double v, double* mu,
                   double* dmu_dv) {
  const double x = std::abs(v) / vs;
  const double xi = std::pow(x, i);
  const double ex = std::exp(-xi);
  *mu = mu_c + (mu_s - mu_c) * ex;
  // d/dv exp(−x^i) = −i x^(i−1) sign(v)/v_s · exp(−x^i)
  *dmu_dv = x > 0.0 ? -(mu_s - mu_c) * ex * i * xi / x * Sign(v) / vs : 0.0;
}

FrictionForce Eval(const CoulombFrictionLaw& l, double v, double fn, double) {
  const double a = std::abs(v);
  double cd = 1.0, dcd = 0.0;
  if (a <= l.stick_velocity) {
    cd = 0.0;
  } else if (a < l.slip_velocity) {
    cd = (a - l.stick_velocity) / (l.slip_velocity - l.stick_velocity);
    dcd = 1.0 / (l.slip_velocity - l.stick_velocity);
  }
  const double s = Sign(v);
  // d(c_d sign v)/dv = dc_d/d|v| (sign² = 1 off zero)
  return {-l.friction_coefficient * cd * fn * s, -l.friction_coefficient * fn * dcd,
          -l.friction_coefficient * cd * s, 0.0};
}

FrictionForce Eval(const ThrelfallFrictionLaw& l, double v, double fn, double) {
  const double e = std::exp(-3.0 * std::abs(v) / l.velocity_scale);
  const double s = Sign(v);
  return {-l.friction_coefficient * fn * (1.0 - e) * s,
          -l.friction_coefficient * fn * 3.0 / l.velocity_scale * e,
          -l.friction_coefficient * (1.0 - e) * s, 0.0};
}

FrictionForce Eval(const StribeckFrictionLaw& l, double v, double fn, double) {
  double mu, dmu;
  StribeckCurve(l.friction_coefficient, l.static_coefficient, l.stribeck_velocity,
                l.stribeck_exponent, v, &mu, &dmu);
  const double s = std::tanh(v / l.regularisation_velocity);
  const double ds = (1.0 - s * s) / l.regularisation_velocity;
  return {-fn * mu * s - l.viscous_coefficient * v,
          -fn * (dmu * s + mu * ds) - l.viscous_coefficient, -mu * s, 0.0};
}

FrictionStateRate LuGreRate(const LuGreFrictionLaw& l, double v, double z) {
  double mu, dmu;
  StribeckCurve(l.friction_coefficient, l.static_coefficient, l.stribeck_velocity, 2.0, v, &mu,
                &dmu);
  // ż = v − |v| z σ̂₀/μ(v)
  const double a = std::abs(v);
  const double g_inv = l.bristle_stiffness / mu;
  const double rate = v - a * z * g_inv;
  const double d_gain_dv = Sign(v) * g_inv - a * l.bristle_stiffness * dmu / (mu * mu);
  return {rate, 1.0 - z * d_gain_dv, -a * g_inv};
}

FrictionForce Eval(const LuGreFrictionLaw& l, double v, double fn, double z) {
  const FrictionStateRate r = LuGreRate(l, v, z);
  const double per_newton =
      l.bristle_stiffness * z + l.bristle_damping * r.rate + l.viscous_coefficient * v;
  return {-fn * per_newton, -fn * (l.bristle_damping * r.d_slip + l.viscous_coefficient),
          -per_newton, -fn * (l.bristle_stiffness + l.bristle_damping * r.d_state)};
}

}  // namespace

const std::vector<std::string>& FrictionLawNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v;
    for (const auto& s : Specs()) v.emplace_back(s.name);
    return v;
  }();
  return names;
}

std::string_view FrictionLawName(const FrictionLaw& law) { return Specs()[law.index()].name; }

ResolvedFrictionLaw ResolveFrictionLaw(std::string_view name, const ParameterMap& overrides) {
  const FrictionSpec* spec = nullptr;
  for (const auto& s : Specs()) {
    if (name == s.name) spec = &s;
  }
  if (spec == nullptr) {
    throw InputError("contact.friction", "\"" + std::string(name) + "\"",
                     "unknown friction law; must be one of: " + Join(FrictionLawNames()));
  }
  Reader r(*spec, overrides);
  FrictionLaw law;
  if (name == "coulomb") {
    CoulombFrictionLaw l;
    l.friction_coefficient = r.Get("friction-coefficient", l.friction_coefficient, "1");
    l.stick_velocity = r.Get("stick-velocity", l.stick_velocity, "m/s");
    l.slip_velocity = r.Get("slip-velocity", l.slip_velocity, "m/s");
    Require(l.slip_velocity > l.stick_velocity, "slip-velocity", l.slip_velocity,
            "must be > stick-velocity = " + FormatValue(l.stick_velocity) + " m/s");
    law = l;
  } else if (name == "threlfall") {
    ThrelfallFrictionLaw l;
    l.friction_coefficient = r.Get("friction-coefficient", l.friction_coefficient, "1");
    l.velocity_scale = r.Get("velocity-scale", l.velocity_scale, "m/s");
    law = l;
  } else if (name == "stribeck" || name == "lugre") {
    const double mu_c = r.Get("friction-coefficient", kDefaultFrictionCoefficient, "1");
    const double mu_s = r.Get("static-coefficient", 1.5 * mu_c, "1");
    Require(mu_s >= mu_c, "static-coefficient", mu_s,
            "must be >= friction-coefficient = " + FormatValue(mu_c));
    if (name == "stribeck") {
      StribeckFrictionLaw l;
      l.friction_coefficient = mu_c;
      l.static_coefficient = mu_s;
      l.stribeck_velocity = r.Get("stribeck-velocity", l.stribeck_velocity, "m/s");
      l.stribeck_exponent = r.Get("stribeck-exponent", l.stribeck_exponent, "1");
      l.viscous_coefficient = r.Get("viscous-coefficient", l.viscous_coefficient, "N*s/m");
      l.regularisation_velocity =
          r.Get("regularisation-velocity", l.regularisation_velocity, "m/s");
      law = l;
    } else {
      LuGreFrictionLaw l;
      l.friction_coefficient = mu_c;
      l.static_coefficient = mu_s;
      l.stribeck_velocity = r.Get("stribeck-velocity", l.stribeck_velocity, "m/s");
      l.bristle_stiffness = r.Get("bristle-stiffness", l.bristle_stiffness, "1/m");
      l.bristle_damping = r.Get("bristle-damping", l.bristle_damping, "s/m");
      l.viscous_coefficient = r.Get("viscous-coefficient", l.viscous_coefficient, "s/m");
      law = l;
    }
  }
  return {law, r.Take()};
}

int NumFrictionStates(const FrictionLaw& law) {
  return std::holds_alternative<LuGreFrictionLaw>(law) ? 1 : 0;
}

FrictionForce CalcFrictionForce(const FrictionLaw& law, double slip_velocity, double normal_force,
                                double state) {
  return std::visit([&](const auto& l) { return Eval(l, slip_velocity, normal_force, state); },
                    law);
}

FrictionStateRate CalcFrictionStateRate(const FrictionLaw& law, double slip_velocity,
                                        double state) {
  if (const auto* l = std::get_if<LuGreFrictionLaw>(&law))
    return LuGreRate(*l, slip_velocity, state);
  return {};
}

}  // namespace flexrod::contact
