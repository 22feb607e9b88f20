// tests/multibody/clearance_fixture.h — shared fixtures of the clearance-joint tests: the
// rig's pin-in-bush geometry (R_bush = 9.525 mm, c = 0.5 mm, L = 12.7 mm, steel on steel), a
// two-body mechanism (a bush body held by a ground joint, a free pin body, no gravity) joined
// by a ClearanceJoint, and the joint's prescribed-kinematics helpers.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "contact/friction_law.h"
#include "contact/normal_law.h"
#include "multibody/clearance_joint.h"
#include "multibody/mechanism.h"
#include "multibody/simulate.h"

namespace flexrod::multibody::testing {

inline contact::ContactGeometry RigJointGeometry() { return {9.525e-3, 9.025e-3, 12.7e-3}; }

inline contact::ContactMaterials SteelOnSteel(double restitution) {
  return {200e9, 0.29, 200e9, 0.29, restitution};
}

inline contact::NormalLaw RigLaw(const std::string& name, double restitution,
                                 const contact::ParameterMap& overrides = {}) {
  return contact::MakeNormalLaw(name, SteelOnSteel(restitution), RigJointGeometry(), overrides);
}

struct PinInBush {
  Mechanism model;
  BodyId bush, pin;
  MarkerId bush_centre, pin_centre;
  ElementId joint;
  std::shared_ptr<const ClearanceJoint> element;
};

/// Bush body fixed at the origin (ground joint), pin body free, joined by the clearance joint.
inline PinInBush BuildPinInBush(const contact::NormalLaw& law,
                                std::optional<contact::FrictionLaw> friction, double pin_mass = 1.0,
                                double pin_inertia = 1e-4) {
  PinInBush p;
  MechanismBuilder b;
  p.bush = b.AddRigidBody({"bush", 2.0, 1e-3, Vec2::Zero()});
  b.AddGroundJoint("bush-fixed", p.bush, Vec2::Zero(), 0.0);
  p.pin = b.AddRigidBody({"pin", pin_mass, pin_inertia, Vec2::Zero()});
  p.bush_centre = b.AddBodyMarker(p.bush, "bush-centre", Vec2::Zero());
  p.pin_centre = b.AddBodyMarker(p.pin, "pin-centre", Vec2::Zero());
  p.element = std::make_shared<const ClearanceJoint>(RigJointGeometry(), law, friction);
  p.joint = b.AddForceElement("clearance", p.bush_centre, p.pin_centre, p.element);
  p.model = b.Build();
  return p;
}

/// Initial state: pin centre at `position` with `velocity` and spin `spin` [rad/s].
inline InitialConditionSpec PinStart(const PinInBush& p, const Vec2& position, const Vec2& velocity,
                                     double spin) {
  InitialConditionSpec ic;
  ic.coordinates = Vec::Zero(p.model.num_coordinates());
  ic.velocities = Vec::Zero(p.model.num_coordinates());
  SetBodyPose(p.model, p.pin, position, 0.0, &ic.coordinates);
  SetBodyVelocity(p.model, p.pin, velocity, spin, &ic.velocities);
  return ic;
}

}  // namespace flexrod::multibody::testing
