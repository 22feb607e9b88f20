// mechanisms/joint_config.cc — the clearance joint from joint.* keys (see joint_config.h).
// SPDX-License-Identifier: GPL-3.0-or-later
#include "mechanisms/joint_config.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "common/error.h"
#include "fem/material.h"

namespace flexrod {
namespace {

/// Input key ↔ contact parameter key of the normal-law overrides.
struct OverrideKey {
  const char* input;
  const char* parameter;
};
constexpr OverrideKey kLawOverrides[] = {
    {"joint.stiffness", "stiffness"},
    {"joint.exponent", "exponent"},
    {"joint.damping", "damping"},
    {"joint.effective_mass", "effective-mass"},
    {"joint.working_penetration", "working-penetration"},
    {"joint.min_approach_velocity", "min-approach-velocity"},
};

/// The joint.* key a contact-layer InputError refers to.
std::string JointKeyFor(const std::string& contact_key) {
  for (const OverrideKey& k : kLawOverrides) {
    if (contact_key == k.parameter) return k.input;
  }
  if (contact_key == "contact.law") return "joint.law";
  if (contact_key == "contact.friction") return "joint.friction_law";
  if (contact_key == "friction-coefficient" || contact_key == "static-coefficient") {
    return "joint.friction";
  }
  if (contact_key == "contact.restitution" || contact_key == "restitution") {
    return "joint.restitution";
  }
  if (contact_key == "contact.pin_radius" || contact_key == "contact.clearance") {
    return "joint.clearance";
  }
  if (contact_key == "contact.bush_radius") return "joint.bush_radius";
  if (contact_key == "contact.length") return "joint.length";
  if (contact_key.rfind("contact.pin_", 0) == 0) return "joint.pin_material";
  if (contact_key.rfind("contact.bush_", 0) == 0) return "joint.bush_material";
  std::string key = contact_key;
  std::replace(key.begin(), key.end(), '-', '_');
  return "joint." + key;
}

/// Runs a contact-layer resolution, re-keying its InputError to the joint.* input key.
template <typename Fn>
auto Rekeyed(Fn&& fn) -> decltype(fn()) {
  try {
    return fn();
  } catch (const InputError& e) {
    throw InputError(JointKeyFor(e.key()), e.value(), e.rule());
  }
}

fem::Material JointMaterial(const Config& cfg, const std::string& key) {
  try {
    return fem::MaterialByName(cfg.Text(key));
  } catch (const InputError& e) {
    throw InputError(key, e.value(), e.rule());
  }
}

void Add(std::vector<contact::ResolvedParameter>* out, std::string name, double value,
         std::string unit, std::string source) {
  out->push_back({std::move(name), value, std::move(unit), std::move(source)});
}

std::string SourceOf(const Config& cfg, const std::string& key) {
  return cfg.IsSet(key) ? "input" : "default";
}

/// joint.clearance, joint.bush_radius, joint.length: the pin-in-bush geometry, checked.
void ResolveGeometry(const Config& cfg, ClearanceJointConfig* joint) {
  ClearanceJointConfig& jc = *joint;
  std::vector<contact::ResolvedParameter>& rec = jc.parameters;
  const double clearance = cfg.Quantity("joint.clearance");
  const double bush_radius = cfg.Quantity("joint.bush_radius");
  const double length = cfg.Quantity("joint.length");
  Require(std::isfinite(clearance) && clearance > 0.0, "joint.clearance", clearance,
          "the radial clearance R_bush - R_pin must be > 0 [m]");
  Require(std::isfinite(bush_radius) && bush_radius > 0.0, "joint.bush_radius", bush_radius,
          "must be > 0 [m]");
  Require(bush_radius - clearance > 0.0, "joint.clearance", clearance,
          "must be < joint.bush_radius = " + FormatValue(bush_radius) +
              " m: the pin radius R_bush - clearance must be > 0");
  Require(std::isfinite(length) && length > 0.0, "joint.length", length,
          "the bearing length must be > 0 [m]");
  jc.geometry = {bush_radius, bush_radius - clearance, length};
  Add(&rec, "joint.bush_radius", bush_radius, "m", SourceOf(cfg, "joint.bush_radius"));
  Add(&rec, "joint.clearance", clearance, "m", SourceOf(cfg, "joint.clearance"));
  Add(&rec, "joint.pin_radius", jc.geometry.pin_radius, "m", "derived");
  Add(&rec, "joint.length", length, "m", SourceOf(cfg, "joint.length"));
}

/// The pin's and bush's materials and the restitution, checked.
void ResolveMaterials(const Config& cfg, ClearanceJointConfig* joint) {
  ClearanceJointConfig& jc = *joint;
  std::vector<contact::ResolvedParameter>& rec = jc.parameters;
  const double restitution = cfg.Quantity("joint.restitution");
  Require(std::isfinite(restitution) && restitution > 0.0 && restitution <= 1.0,
          "joint.restitution", restitution, "the coefficient of restitution must lie in (0, 1]");
  const fem::Material pin = JointMaterial(cfg, "joint.pin_material");
  const fem::Material bush = JointMaterial(cfg, "joint.bush_material");
  jc.materials = {pin.youngs_modulus, pin.poisson_ratio, bush.youngs_modulus, bush.poisson_ratio,
                  restitution};
  Rekeyed([&] {
    jc.materials.Validate();
    return 0;
  });
  Add(&rec, "joint.pin_E", pin.youngs_modulus, "Pa", "derived");
  Add(&rec, "joint.pin_nu", pin.poisson_ratio, "1", "derived");
  Add(&rec, "joint.bush_E", bush.youngs_modulus, "Pa", "derived");
  Add(&rec, "joint.bush_nu", bush.poisson_ratio, "1", "derived");
}

/// joint.law with its overrides (0 = derived), the effective mass from the slider where the
/// law takes one and the input leaves it out.
void ResolveNormal(const Config& cfg, double default_effective_mass, ClearanceJointConfig* joint) {
  ClearanceJointConfig& jc = *joint;
  std::vector<contact::ResolvedParameter>& rec = jc.parameters;
  const double restitution = jc.materials.restitution;
  const std::string law = cfg.Text("joint.law");
  const std::vector<std::string>& accepted = Rekeyed(
      [&]() -> const std::vector<std::string>& { return contact::NormalLawParameterKeys(law); });
  // An override is given when its value is not 0 (0 = derived; this keeps a written resolved
  // input loadable as an input).
  contact::ParameterMap overrides;
  for (const OverrideKey& k : kLawOverrides) {
    const double v = cfg.Quantity(k.input);
    if (v != 0.0) overrides[k.parameter] = v;
  }
  // A restitution given (other than its default, which a written resolved input lists) is an
  // override too: a law without hysteresis damping (Hertz, linear spring, line laws) refuses it.
  if (cfg.IsSet("joint.restitution") && restitution != Config().Quantity("joint.restitution")) {
    overrides["restitution"] = restitution;
  }
  const bool takes_mass =
      std::find(accepted.begin(), accepted.end(), "effective-mass") != accepted.end();
  const bool derived_mass = takes_mass && overrides.count("effective-mass") == 0;
  if (derived_mass) {
    RequirePositive("slider.mass", default_effective_mass);
    overrides["effective-mass"] = default_effective_mass;
  }
  contact::ResolvedNormalLaw normal =
      Rekeyed([&] { return contact::ResolveNormalLaw(law, jc.materials, jc.geometry, overrides); });
  jc.normal_law = std::move(normal.law);
  for (contact::ResolvedParameter& p : normal.parameters) {
    if (p.name == "effective-mass" && derived_mass) p.source = "derived (slider.mass)";
    if (p.name == "restitution" && !cfg.IsSet("joint.restitution")) p.source = "default";
    Add(&rec, "joint.law." + p.name, p.value, p.unit, p.source);
  }
}

/// joint.friction_law with joint.friction (none: no friction law).
void ResolveFriction(const Config& cfg, ClearanceJointConfig* joint) {
  ClearanceJointConfig& jc = *joint;
  std::vector<contact::ResolvedParameter>& rec = jc.parameters;
  const std::string friction = cfg.Text("joint.friction_law");
  if (friction != "none") {
    const double mu = cfg.Quantity("joint.friction");
    Require(std::isfinite(mu) && mu > 0.0, "joint.friction", mu,
            "the friction coefficient must be > 0 (use joint.friction_law = none for a "
            "frictionless joint)");
    contact::ResolvedFrictionLaw fl = Rekeyed([&] {
      return contact::ResolveFrictionLaw(friction, {{"friction-coefficient", mu}});
    });
    jc.friction_law = fl.law;
    for (contact::ResolvedParameter& p : fl.parameters) {
      if (p.name == "friction-coefficient") p.source = SourceOf(cfg, "joint.friction");
      Add(&rec, "joint.friction_law." + p.name, p.value, p.unit, p.source);
    }
  }
}

}  // namespace

ClearanceJointConfig ResolveClearanceJoint(const Config& cfg, double default_effective_mass) {
  ClearanceJointConfig jc;
  ResolveGeometry(cfg, &jc);
  ResolveMaterials(cfg, &jc);
  ResolveNormal(cfg, default_effective_mass, &jc);
  ResolveFriction(cfg, &jc);
  return jc;
}

std::shared_ptr<const multibody::ClearanceJoint> MakeClearanceJoint(
    const ClearanceJointConfig& joint) {
  return std::make_shared<const multibody::ClearanceJoint>(joint.geometry, joint.normal_law,
                                                           joint.friction_law);
}

}  // namespace flexrod
