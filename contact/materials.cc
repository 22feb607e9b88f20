// contact/materials.cc — the contact's materials and geometry: their checks, the compliance of
// a material, the effective modulus, and the Hertz stiffness of a pin in a bush
// (formulas and sources: contact/normal_law.h).
// SPDX-License-Identifier: GPL-3.0-or-later
#include <cmath>
#include <numbers>

#include "common/error.h"
#include "contact/normal_law.h"

namespace flexrod::contact {

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

}  // namespace flexrod::contact
