// run/contact_impact.h — `flexrod contact` and flexrod.contact() in Python: one impact of a
// mass against a rigid wall through a named normal contact law, the law's parameters derived
// from the pin and bush materials and geometry unless given; the flags (keyword arguments)
// that give them, and the JSON of the result. What does not live here: the laws and the
// impact integration (contact/), printing and plotting (app/cmd_contact.cc).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "common/units.h"
#include "contact/impact.h"
#include "contact/normal_law.h"

namespace flexrod {

/// A law parameter of `flexrod contact --<key>` (flexrod.contact(<key with _>=...)).
struct ContactLawFlag {
  const char* key;  ///< override key of contact/normal_law.h, e.g. "working-penetration"
  Dimension dim;
  const char* help;  ///< with the unit
};
const std::vector<ContactLawFlag>& ContactLawFlags();

/// The request as typed: values are text with units ("2.71 kg"); empty = default.
struct ContactRequest {
  std::string law;
  std::string mass, velocity;                  ///< impacting mass [kg], approach speed [m/s]
  std::string pin_E, pin_nu, bush_E, bush_nu;  ///< default steel
  /// Default joint: steel pin in a steel bush with the flexible rig's 3/4 in bore (RIG.md §2)
  /// and 0.5 mm radial clearance; the bearing length is assumed (1/2 in), not given by the
  /// thesis.
  std::string pin_radius{"9.025 mm"}, bush_radius{"9.525 mm"}, length{"12.7 mm"};
  std::vector<std::pair<std::string, std::string>> law_params;  ///< (key, text) in order
};

struct ContactImpact {
  std::string law;
  double mass{0.0};      ///< [kg]
  double velocity{0.0};  ///< [m/s]
  contact::ContactMaterials materials;
  contact::ContactGeometry geometry;
  std::vector<contact::ResolvedParameter> parameters;  ///< the law's, resolved
  contact::ImpactResult result;
  std::string warning;  ///< "" if none
};

/// Parses and checks everything (InputError naming the flag: "mass", "pin-radius", ...), then
/// simulates the impact.
ContactImpact SimulateContactImpact(const ContactRequest& request);

/// What `flexrod contact --json` writes: law, the figures (achieved_restitution, peak_force,
/// peak_penetration, contact_duration, dissipated_energy, outgoing_speed) with "units", the
/// "inputs", the resolved "parameters" and any "warnings". Non-finite numbers are null.
nlohmann::json ContactJson(const ContactImpact& impact);

}  // namespace flexrod
