// mechanisms/joint_config.h — the clearance (pin-in-bush) small-end joint from the input keys
// joint.*: geometry (clearance, bush radius, bearing length), pin and bush materials, the
// normal contact law by name with its overrides, the friction law and coefficient; every
// value validated with an InputError naming the joint.* key, and the resolved contact
// parameters as (key, value, unit, source) records for the run's resolved input. What does not
// live here: the laws (contact/), the force element (multibody/clearance_joint.h), where the
// joint sits in the mechanism (mechanisms/recipe_slider_crank.cc).
//
// Override keys joint.stiffness, joint.exponent, joint.damping, joint.effective_mass,
// joint.working_penetration, joint.min_approach_velocity: 0 (the default) means "derived from
// materials, geometry and restitution"; any other value is passed to the law, and a law that
// does not take it rejects it with InputError("joint.<key>", value, "law '...' does not take
// this parameter; it takes: ...") (contact's ParameterMap validation, re-keyed to the input
// key). The 0 convention keeps a written resolved input (every key, defaults included) loadable
// as an input. joint.restitution and the materials are properties of the pin–bush pair: laws
// without damping do not use them. joint.effective_mass defaults to the slider mass for the
// laws that calibrate damping to the restitution (kelvin-voigt, maxwell, standard-linear-solid,
// impact). joint.friction is not used with joint.friction_law = none.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "contact/friction_law.h"
#include "contact/geometry.h"
#include "contact/normal_law.h"
#include "input/config.h"
#include "multibody/clearance_joint.h"

namespace flexrod {

/// The clearance joint as resolved from the input.
struct ClearanceJointConfig {
  contact::ContactGeometry geometry;    ///< R_bush, R_pin = R_bush − c, L [m]
  contact::ContactMaterials materials;  ///< pin/bush E [Pa], ν [-], restitution [-]
  contact::NormalLaw normal_law;
  std::optional<contact::FrictionLaw> friction_law;  ///< nullopt: joint.friction_law = none
  /// Resolved parameters, SI: "joint.pin_radius", ..., "joint.law.<param>",
  /// "joint.friction_law.<param>" with unit and source ("input", "derived", "default").
  std::vector<contact::ResolvedParameter> parameters;
};

/// Resolves joint.* (any joint.type; the caller decides whether to use it).
/// `default_effective_mass` [kg] > 0: the effective mass of the impact when joint.effective_mass
/// is not set (the slider-crank passes the slider mass). Throws InputError naming the joint.*
/// key: clearance ≤ 0, pin radius R_bush − c ≤ 0, length ≤ 0, restitution ∉ (0, 1], an unknown
/// law, a non-zero override the law does not take, a value outside its rule, μ ≤ 0 with a
/// friction law.
ClearanceJointConfig ResolveClearanceJoint(const Config& cfg, double default_effective_mass);

/// The force element for a resolved joint.
std::shared_ptr<const multibody::ClearanceJoint> MakeClearanceJoint(
    const ClearanceJointConfig& joint);

}  // namespace flexrod
