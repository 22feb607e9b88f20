// contact/normal_law_calibration.cc — what the normal laws' resolution calibrates with (see
// contact/normal_law_calibration.h): damping from a restitution, power-law fits over the
// working range, the line-contact log curves.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "contact/normal_law_calibration.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_integration.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <string>

#include "common/error.h"
#include "contact/golden_section.h"
#include "contact/impact.h"

namespace flexrod::contact::normal_law_calibration {
namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

// ---- line-contact log curves -----------------------------------------------------------------

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
  const GoldenBracket min = GoldenSectionMinimum(e_of, std::log(1e-3), std::log(1e3), 40, 0.0);
  const double log_eta_min = 0.5 * (min.a + min.b);
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

PowerFit FitPowerLaw(const std::function<double(double)>& force, double exponent,
                     double working_penetration) {
  struct Ctx {
    const std::function<double(double)>* f;
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

}  // namespace flexrod::contact::normal_law_calibration

namespace flexrod::contact {

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
