// tests/contact/contact_test_util.h — shared inputs for the contact tests: a steel pin in a
// steel bush of the flexible rig's size, and every normal law built from them.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <string>
#include <vector>

#include "contact/normal_law.h"

namespace flexrod::contact::testing {

/// Steel (E = 200 GPa, ν = 0.29) against steel, restitution 0.8.
inline ContactMaterials SteelPair(double restitution = 0.8) {
  return ContactMaterials{200e9, 0.29, 200e9, 0.29, restitution};
}

/// 3/4 in bore (R_b = 9.525 mm), 0.5 mm radial clearance, 12.7 mm bearing length.
inline ContactGeometry RigGeometry() { return ContactGeometry{9.525e-3, 9.025e-3, 12.7e-3}; }

/// The overrides a law needs beyond materials and geometry: the effective mass for laws whose
/// damping is calibrated on a single impact; for the standard linear solid also a stiff arm
/// (k₂ ≈ 120 k₁) so that restitutions down to 0.03 are reachable.
inline ParameterMap NeededOverrides(const std::string& name, double mass = 1.0) {
  if (name == "standard-linear-solid") {
    return ParameterMap{{"effective-mass", mass}, {"stiffness-2", 1e10}};
  }
  for (const std::string& key : NormalLawParameterKeys(name)) {
    if (key == "effective-mass") return ParameterMap{{"effective-mass", mass}};
  }
  return {};
}

struct NamedLaw {
  std::string name;
  NormalLaw law;
};

inline std::vector<NamedLaw> AllLaws(double restitution = 0.8) {
  std::vector<NamedLaw> laws;
  for (const std::string& name : NormalLawNames()) {
    laws.push_back(
        {name, MakeNormalLaw(name, SteelPair(restitution), RigGeometry(), NeededOverrides(name))});
  }
  return laws;
}

/// A representative penetration [m] for the steel pair: a few micrometres.
inline constexpr double kTypicalPenetration = 4e-6;

}  // namespace flexrod::contact::testing
