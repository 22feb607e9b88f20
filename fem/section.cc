// fem/section.cc — rectangular section properties: second moments for the selected in-plane
// axis, the Saint-Venant torsion constant and Cowper's shear coefficient.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "fem/section.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "common/error.h"

namespace flexrod::fem {

BendingAxis BendingAxisFromString(const std::string& key, const std::string& value) {
  if (value == "weak") return BendingAxis::kWeak;
  if (value == "strong") return BendingAxis::kStrong;
  throw InputError(key, value, "must be \"weak\" or \"strong\"");
}

const char* ToString(BendingAxis axis) { return axis == BendingAxis::kWeak ? "weak" : "strong"; }

double RectSection::inertia_in_plane() const {
  return in_plane == BendingAxis::kWeak ? height * thickness * thickness * thickness / 12.0
                                        : thickness * height * height * height / 12.0;
}

double RectSection::inertia_out_of_plane() const {
  return in_plane == BendingAxis::kWeak ? thickness * height * height * height / 12.0
                                        : height * thickness * thickness * thickness / 12.0;
}

double RectSection::half_depth_in_plane() const {
  return in_plane == BendingAxis::kWeak ? 0.5 * thickness : 0.5 * height;
}

// Saint-Venant torsion of an a × b rectangle, a ≥ b (Timoshenko & Goodier, Theory of
// Elasticity, 3rd ed., §109, eq. (168)):
//   J = a b³ [1/3 − (64/π⁵)(b/a) Σ_{n=1,3,5,...} tanh(nπa/(2b)) / n⁵].
// The series is summed as Σ 1/n⁵ − Σ (1 − tanh(z_n))/n⁵ with Σ_{odd n} 1/n⁵ = (31/32) ζ(5);
// the second sum decays like e^{−nπ a/b}, so a few terms reach machine precision.
double RectSection::torsion_constant() const {
  const double a = std::max(thickness, height);
  const double b = std::min(thickness, height);
  constexpr double kOddZeta5 = 1.0045237627951396161;  // (31/32) ζ(5)
  constexpr double kPi = std::numbers::pi;
  double correction = 0.0;
  for (int n = 1; n < 1000; n += 2) {
    const double z = n * kPi * a / (2.0 * b);
    const double e = std::exp(-2.0 * z);
    const double one_minus_tanh = 2.0 * e / (1.0 + e);
    const double term = one_minus_tanh / std::pow(static_cast<double>(n), 5);
    correction += term;
    if (term < 1e-18) break;
  }
  const double series = kOddZeta5 - correction;
  return a * b * b * b * (1.0 / 3.0 - 64.0 / std::pow(kPi, 5) * (b / a) * series);
}

// Cowper, G. R. (1966), "The shear coefficient in Timoshenko's beam theory", J. Appl. Mech.
// 33(2):335–340, rectangle: κ = 10(1+ν)/(12+11ν).
double RectSection::CowperShearFactor(double poisson_ratio) {
  return 10.0 * (1.0 + poisson_ratio) / (12.0 + 11.0 * poisson_ratio);
}

void RectSection::Validate(const std::string& prefix) const {
  auto check = [&](const std::string& field, double value) {
    if (!(std::isfinite(value) && value > 0.0)) {
      throw InputError(prefix + "." + field, FormatValue(value) + " m", "must be finite and > 0");
    }
  };
  check("thickness", thickness);
  check("height", height);
  // in_plane comes from BendingAxisFromString, which rejects bad input; anything else is a bug.
  FLEXROD_ASSERT(in_plane == BendingAxis::kWeak || in_plane == BendingAxis::kStrong);
}

}  // namespace flexrod::fem
