// fem/material.h — isotropic linear-elastic materials (value types) and the built-in library.
// What does not live here: sections (fem/section.h), elements (fem/beam_element.h).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <string>
#include <vector>

namespace flexrod::fem {

struct Material {
  std::string name;       ///< "steel", "brass", "aluminium" or a user name
  double youngs_modulus;  ///< E [Pa], > 0
  double poisson_ratio;   ///< ν [-], in (-1, 0.5)
  double density;         ///< ρ [kg/m^3], > 0
  double yield_strength;  ///< σ_y [Pa], > 0
  /// η [-], >= 0: the material's loss factor (internal damping of the solid, damping.type =
  /// material: every mode gets ζ = η / 2, the viscous equivalent at resonance of hysteretic
  /// damping)
  double loss_factor{0.0};
  std::string source;  ///< where the numbers come from

  double shear_modulus() const { return youngs_modulus / (2.0 * (1.0 + poisson_ratio)); }
  /// Throws InputError naming `prefix`.<field> for any invalid value.
  void Validate(const std::string& prefix = "material") const;
};

/// Built-in materials by name ("steel", "brass", "aluminium"; "aluminum" accepted).
/// Throws InputError("material", name, "must be one of ...") otherwise.
Material MaterialByName(const std::string& name);
std::vector<std::string> MaterialNames();

}  // namespace flexrod::fem
