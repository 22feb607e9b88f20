// contact/normal_law_detail.h — what the normal laws' evaluation (contact/normal_law.cc) and
// their parameter resolution (contact/normal_law_resolve.cc) share: the table of law names and
// accepted keys, and the line-contact log curves. Internal to contact/.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "contact/normal_law.h"

namespace flexrod::contact::normal_law_detail {

inline constexpr double kInf = std::numeric_limits<double>::infinity();

/// A law's name and the parameter keys it accepts.
struct LawSpec {
  const char* name;
  std::vector<std::string> keys;
};

/// Every law, in the order of the NormalLaw variant.
const std::vector<LawSpec>& LawSpecs();
/// The law named `name`; an InputError naming contact.law if none.
const LawSpec& FindSpec(std::string_view name);
/// The names joined with ", ".
std::string JoinNames(const std::vector<std::string>& names);
/// "N/m" for a linear law, "N/m^n" otherwise.
std::string StiffnessUnit(double exponent);

// ---- line-contact log curves: δ = a F [ln(b/F) + c₀] ---------------------------------------
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

}  // namespace flexrod::contact::normal_law_detail
