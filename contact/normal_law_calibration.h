// contact/normal_law_calibration.h — Internal to contact/: the numerical calibrations the normal
// laws' parameter resolution (contact/normal_law.cc) uses: damping from a coefficient of
// restitution, power-law fits over the working range, and the line-contact log curves
// δ = a F [ln(b/F) + c₀] of a pin in a bush.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <functional>

#include "contact/normal_law.h"

namespace flexrod::contact::normal_law_calibration {

// ---- line-contact log curves ---------------------------------------------------------------
/// δ at force F [m] (0 for F ≤ 0).
double CurvePenetration(const LogLineCurve& c, double force);
/// The force and penetration at the end of the curve's monotone branch [N], [m].
double CurveLimitForce(const LogLineCurve& c);
double CurveLimitPenetration(const LogLineCurve& c);
/// F(δ) and dF/dδ on the monotone branch (beyond it, continued with the secant slope).
void SolveCurve(const LogLineCurve& c, double penetration, double* force, double* slope);
/// The ESDU 78035, Johnson and Dubowsky–Freudenstein curves of a pin in a bush.
LogLineCurve EsduCurve(double compliance, double length, double clearance);
LogLineCurve JohnsonCurve(double compliance, double length, double clearance);
LogLineCurve DubowskyFreudensteinCurve(double compliance, double length, double clearance,
                                       double bush_radius, double pin_radius);

// ---- damping from restitution --------------------------------------------------------------
/// Kelvin–Voigt: the damping ratio ζ whose restitution is `restitution` (inverse of
/// KelvinVoigtRestitution).
double KelvinVoigtDampingRatio(double restitution);
/// Maxwell: ζ = −ln cₑ/√(π² + ln²cₑ).
double MaxwellDampingRatio(double restitution);
/// The standard linear solid's restitution for springs k1, k2, dashpot `damping`, mass.
double SlsRestitution(double k1, double k2, double damping, double mass);
/// The standard linear solid's dashpot for a restitution (on the large-damping branch);
/// InputError if the springs cannot reach it.
double SlsDamping(double k1, double k2, double mass, double restitution);
/// ADAMS IMPACT: c_max for a restitution at one impact of `mass` at `speed`.
double ImpactDamping(double k, double n, double dmax, double mass, double speed,
                     double restitution);

// ---- power-law fits over the working range -------------------------------------------------
/// Least-squares fit of F(δ) by Kδⁿ over [0, δ_w]: K = (2n+1)/δ_w^(2n+1) ∫₀^δ_w F δⁿ dδ; also R².
struct PowerFit {
  double stiffness;
  double r_squared;
};
PowerFit FitPowerLaw(const std::function<double(double)>& force, double exponent,
                     double working_penetration);
/// Hertz K δ^1.5 fitted by kδ over [0, δ_w]: k = (6/7)K√δ_w.
double LinearisedHertz(double hertz_stiffness, double working_penetration);

}  // namespace flexrod::contact::normal_law_calibration
