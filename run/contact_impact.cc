// SPDX-License-Identifier: GPL-3.0-or-later
#include "run/contact_impact.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "fem/material.h"

namespace flexrod {
namespace {

bool IsLinearLaw(const std::string& law) {
  return law == "linear-spring" || law == "kelvin-voigt" || law == "maxwell" ||
         law == "standard-linear-solid";
}

nlohmann::json Number(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

}  // namespace

// Stiffness is special: N/m for the linear laws, N/m^n (bare SI number) for the power laws.
const std::vector<ContactLawFlag>& ContactLawFlags() {
  static const std::vector<ContactLawFlag> kFlags = {
      {"restitution", Dimension::kDimensionless, "coefficient of restitution c_e in (0, 1]"},
      {"stiffness", Dimension::kStiffness, "K [N/m^n, bare SI number] (k [N/m] for linear laws)"},
      {"exponent", Dimension::kDimensionless, "force exponent n"},
      {"damping", Dimension::kDamping, "dashpot damping d, e.g. \"2000 N*s/m\""},
      {"stiffness-2", Dimension::kStiffness, "standard-linear-solid arm stiffness k2"},
      {"working-penetration", Dimension::kLength,
       "fit range of hybrid/linear laws, e.g. \"10 um\""},
      {"min-approach-velocity", Dimension::kVelocity, "floor on v0 in the hysteresis damping"},
      {"max-damping", Dimension::kDamping, "impact: c_max"},
      {"damping-penetration", Dimension::kLength, "impact: d_max, e.g. \"0.01 mm\""},
      {"calibration-velocity", Dimension::kVelocity,
       "impact: speed for calibrating c_max (default --velocity)"},
      {"compliance", Dimension::kDimensionless, "line laws: sum of h = (1-nu^2)/(pi E) [1/Pa]"},
      {"effective-mass", Dimension::kMass, "mass used to derive damping (default --mass)"},
  };
  return kFlags;
}

namespace {

/// Throws InputError unless `law` is a normal contact law's name.
void CheckLawName(const std::string& law) {
  const auto& names = contact::NormalLawNames();
  if (std::find(names.begin(), names.end(), law) == names.end()) {
    std::string list;
    for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
    throw InputError("law", "\"" + law + "\"",
                     "unknown normal contact law; must be one of: " + list);
  }
}

/// --pin-E, --bush-E, --pin-nu, --bush-nu (steel where not given) and the pin-in-bush geometry.
void ReadMaterialsAndGeometry(const ContactRequest& opt, ContactImpact* impact) {
  ContactImpact& out = *impact;
  const fem::Material steel = fem::MaterialByName("steel");
  contact::ContactMaterials& materials = out.materials;
  materials.pin_youngs_modulus = opt.pin_E.empty()
                                     ? steel.youngs_modulus
                                     : ParseQuantity("pin-E", opt.pin_E, Dimension::kPressure);
  materials.bush_youngs_modulus = opt.bush_E.empty()
                                      ? steel.youngs_modulus
                                      : ParseQuantity("bush-E", opt.bush_E, Dimension::kPressure);
  materials.pin_poisson_ratio =
      opt.pin_nu.empty() ? steel.poisson_ratio
                         : ParseQuantity("pin-nu", opt.pin_nu, Dimension::kDimensionless);
  materials.bush_poisson_ratio =
      opt.bush_nu.empty() ? steel.poisson_ratio
                          : ParseQuantity("bush-nu", opt.bush_nu, Dimension::kDimensionless);
  contact::ContactGeometry& geometry = out.geometry;
  geometry.bush_radius = ParseQuantity("bush-radius", opt.bush_radius, Dimension::kLength);
  geometry.pin_radius = ParseQuantity("pin-radius", opt.pin_radius, Dimension::kLength);
  geometry.length = ParseQuantity("length", opt.length, Dimension::kLength);
}

/// The law's parameters given as flags, in SI; the impacting mass [kg] and speed [m/s] calibrate
/// the laws that take them where the flags leave them out.
contact::ParameterMap ReadLawOverrides(const ContactRequest& opt, double mass, double velocity) {
  contact::ParameterMap overrides;
  for (const auto& [key, text] : opt.law_params) {
    Dimension dim = Dimension::kDimensionless;
    bool known = false;
    for (const ContactLawFlag& f : ContactLawFlags()) {
      if (key == f.key) {
        dim = f.dim;
        known = true;
      }
    }
    if (!known) {
      std::string list;
      for (const ContactLawFlag& f : ContactLawFlags())
        list += std::string(list.empty() ? "" : ", ") + f.key;
      throw InputError(key, "\"" + text + "\"", "unknown law parameter; must be one of: " + list);
    }
    if (key == "stiffness" && !IsLinearLaw(opt.law)) {
      try {
        overrides[key] = ParseQuantity(key, text, Dimension::kDimensionless);
      } catch (const InputError&) {
        throw InputError(key, "\"" + text + "\"",
                         "law '" + opt.law + "' takes K in N/m^n: give it as a bare SI number");
      }
      continue;
    }
    overrides[key] = ParseQuantity(key, text, dim);
  }
  // The impacting mass and speed are the natural calibration inputs of laws that need them.
  const auto& keys = contact::NormalLawParameterKeys(opt.law);
  auto takes = [&](const char* k) { return std::find(keys.begin(), keys.end(), k) != keys.end(); };
  if (takes("effective-mass") && !overrides.count("effective-mass"))
    overrides["effective-mass"] = mass;
  if (takes("calibration-velocity") && !overrides.count("calibration-velocity")) {
    overrides["calibration-velocity"] = velocity;
  }
  return overrides;
}

/// The law resolved from materials and geometry; the contact layer's key names (contact.bush_E,
/// ...) reported as the command's flags (bush-E, ...).
contact::ResolvedNormalLaw ResolveForFlags(const std::string& law,
                                           const contact::ContactMaterials& materials,
                                           const contact::ContactGeometry& geometry,
                                           const contact::ParameterMap& overrides) {
  try {
    return contact::ResolveNormalLaw(law, materials, geometry, overrides);
  } catch (const InputError& e) {
    // The contact layer names its inputs contact.pin_radius, contact.bush_E, ...: report the
    // flag (pin-radius, bush-E, ...; the clearance is set through --pin-radius).
    std::string key = e.key();
    if (key.rfind("contact.", 0) != 0) throw;
    key = key == "contact.clearance" ? "pin-radius" : key.substr(8);
    std::replace(key.begin(), key.end(), '_', '-');
    throw InputError(key, e.value(), e.rule());
  }
}

}  // namespace

ContactImpact SimulateContactImpact(const ContactRequest& opt) {
  // ---- parse and validate everything before any work ----
  CheckLawName(opt.law);
  ContactImpact out;
  out.law = opt.law;
  const double mass = out.mass = ParseQuantity("mass", opt.mass, Dimension::kMass);
  const double velocity = out.velocity =
      ParseQuantity("velocity", opt.velocity, Dimension::kVelocity);
  RequirePositive("mass", mass);
  RequirePositive("velocity", velocity);
  ReadMaterialsAndGeometry(opt, &out);
  const contact::ParameterMap overrides = ReadLawOverrides(opt, mass, velocity);
  const contact::ResolvedNormalLaw resolved =
      ResolveForFlags(opt.law, out.materials, out.geometry, overrides);
  out.parameters = resolved.parameters;

  // ---- work ----
  out.result = contact::SimulateImpact(resolved.law, mass, velocity);
  for (const auto& p : resolved.parameters) {
    if (p.name == "min-approach-velocity" && velocity < p.value) {
      out.warning = "the approach velocity " + FormatValue(velocity) +
                    " m/s is below min-approach-velocity = " + FormatValue(p.value) +
                    " m/s: the hysteresis damping uses the floor, so the achieved restitution "
                    "is above the one this law gives at its own speed; lower "
                    "--min-approach-velocity to remove it";
    }
  }
  return out;
}

nlohmann::json ContactJson(const ContactImpact& c) {
  const contact::ImpactResult& r = c.result;
  nlohmann::json j;
  j["law"] = c.law;
  j["achieved_restitution"] = Number(r.achieved_restitution);
  j["peak_force"] = Number(r.peak_force);
  j["peak_penetration"] = Number(r.peak_penetration);
  j["contact_duration"] = Number(r.contact_duration);
  j["dissipated_energy"] = Number(r.dissipated_energy);
  j["outgoing_speed"] = Number(r.outgoing_speed);
  j["units"] = {{"achieved_restitution", "1"}, {"peak_force", "N"},
                {"peak_penetration", "m"},     {"contact_duration", "s"},
                {"dissipated_energy", "J"},    {"outgoing_speed", "m/s"}};
  j["inputs"] = {{"mass", {{"value", c.mass}, {"unit", "kg"}}},
                 {"velocity", {{"value", c.velocity}, {"unit", "m/s"}}},
                 {"pin-E", {{"value", c.materials.pin_youngs_modulus}, {"unit", "Pa"}}},
                 {"pin-nu", {{"value", c.materials.pin_poisson_ratio}, {"unit", "1"}}},
                 {"bush-E", {{"value", c.materials.bush_youngs_modulus}, {"unit", "Pa"}}},
                 {"bush-nu", {{"value", c.materials.bush_poisson_ratio}, {"unit", "1"}}},
                 {"pin-radius", {{"value", c.geometry.pin_radius}, {"unit", "m"}}},
                 {"bush-radius", {{"value", c.geometry.bush_radius}, {"unit", "m"}}},
                 {"length", {{"value", c.geometry.length}, {"unit", "m"}}}};
  nlohmann::json params = nlohmann::json::array();
  for (const auto& p : c.parameters) {
    params.push_back(
        {{"name", p.name}, {"value", Number(p.value)}, {"unit", p.unit}, {"source", p.source}});
  }
  j["parameters"] = params;
  if (!c.warning.empty()) j["warnings"] = {c.warning};
  return j;
}

}  // namespace flexrod
