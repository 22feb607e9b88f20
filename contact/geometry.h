// contact/geometry.h — geometry of a clearance (pin-in-bush) revolute joint: the validated
// ContactGeometry value type and ClearanceKinematics, a pure function from the planar motion of
// the bush centre and the pin centre (and the angular velocities of the two bodies) to the
// eccentricity, penetration, unit normal, normal rate, contact points and slip velocity; and
// CalcContactLoads, which turns a normal force and a friction force into the equal and opposite
// forces and moments on the two bodies. What does not live here: force laws
// (contact/normal_law.h, contact/friction_law.h) and anything about bodies, frames or joints
// (multibody/). Laws never recompute geometry.
//
// Conventions (2-D, world frame W, SI):
//   e = p_WP − p_WB            pin centre P minus bush centre B
//   c = R_bush − R_pin > 0     radial clearance
//   δ = |e| − c                penetration, > 0 in contact
//   n = e/|e|                  unit normal, from the bush centre towards the pin centre; it
//                              points from the pin into the bush wall at the contact
//   t = (−n_y, n_x)            unit tangent (n rotated by +90°)
//   δ̇ = d|e|/dt = n·(v_P − v_B)  positive while penetrating deeper
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "common/eigen.h"

namespace flexrod::contact {

/// The pin, the bush and the bearing length of a clearance joint.
struct ContactGeometry {
  double bush_radius{0.0};  ///< R_bush: radius of the bore [m], > R_pin
  double pin_radius{0.0};   ///< R_pin: radius of the journal [m], > 0
  double length{0.0};       ///< L: axial length of the line contact [m], > 0

  /// Radial clearance c = R_bush − R_pin [m].
  double clearance() const { return bush_radius - pin_radius; }
  /// Throws InputError ("contact.pin_radius", ...) unless 0 < R_pin < R_bush and L > 0 (all
  /// finite). A pin as large as the bush (zero or negative clearance) is rejected.
  void Validate() const;
};

/// Motion of the two joint elements at one instant (world frame, planar).
struct ClearanceMotion {
  Vec2 bush_centre{Vec2::Zero()};     ///< p_WB [m]
  Vec2 bush_velocity{Vec2::Zero()};   ///< v_WB [m/s]
  double bush_angular_velocity{0.0};  ///< ω of the body carrying the bush [rad/s]
  Vec2 pin_centre{Vec2::Zero()};      ///< p_WP [m]
  Vec2 pin_velocity{Vec2::Zero()};    ///< v_WP [m/s]
  double pin_angular_velocity{0.0};   ///< ω of the body carrying the pin [rad/s]
};

/// Below this |e| [m] the normal direction is undefined; the joint is then certainly open
/// (δ = −c < 0), n is set to (1, 0) and normal_defined = false.
inline constexpr double kMinEccentricity = 1e-15;

/// Everything a normal law and a friction law need, and where their forces act.
struct ClearanceKinematics {
  Vec2 eccentricity{Vec2::Zero()};  ///< e = p_WP − p_WB [m]
  double eccentricity_norm{0.0};    ///< |e| [m]
  double penetration{0.0};          ///< δ = |e| − c [m]; > 0 in contact
  double penetration_rate{0.0};     ///< δ̇ = d|e|/dt = n·(v_P − v_B) [m/s]; > 0 approaching
  Vec2 normal{1.0, 0.0};            ///< n = e/|e| [-], unit
  Vec2 tangent{0.0, 1.0};           ///< t = (−n_y, n_x) [-], unit
  bool normal_defined{false};       ///< false if |e| < kMinEccentricity
  Vec2 bush_contact_point{Vec2::Zero()};  ///< Q_B = p_WB + R_bush n [m], on the bore surface
  Vec2 pin_contact_point{Vec2::Zero()};   ///< Q_P = p_WP + R_pin n [m], on the pin surface
  /// Velocity of the pin's material point at Q_P minus that of the bush's material point at
  /// Q_B: (v_P + ω_P R_pin t) − (v_B + ω_B R_bush t) [m/s].
  Vec2 relative_velocity{Vec2::Zero()};
  /// Slip velocity v_t = t·relative_velocity = t·(v_P − v_B) + ω_P R_pin − ω_B R_bush [m/s].
  double slip_velocity{0.0};
};

/// Pure function of the instantaneous motion. Valid for any δ (open or closed joint).
ClearanceKinematics CalcClearanceKinematics(const ContactGeometry& geometry,
                                            const ClearanceMotion& motion);

/// Forces and moments exerted by the contact on the two bodies.
///
/// A normal force F_n ≥ 0 [N] (from a normal law) pushes the pin back towards the bush centre
/// and the bush outwards; a friction force F_t [N] (from a friction law, F_t·v_t ≤ 0) acts on the
/// pin along +t and on the bush along −t:
///   force_on_pin  = −F_n n + F_t t,   applied at Q_P
///   force_on_bush = +F_n n − F_t t,   applied at Q_B   (= −force_on_pin)
/// The normal force passes through both centres, so only friction has a moment about them:
///   moment_on_pin  = (Q_P − p_WP) × force_on_pin  = +R_pin  F_t
///   moment_on_bush = (Q_B − p_WB) × force_on_bush = −R_bush F_t
/// A body whose reference point is not the circle centre adds (centre − reference) × force.
/// The mechanical power of the pair is −F_n δ̇ + F_t v_t (tested).
struct ContactLoads {
  Vec2 force_on_pin{Vec2::Zero()};            ///< [N], applied at pin_application_point
  Vec2 force_on_bush{Vec2::Zero()};           ///< [N], applied at bush_application_point
  Vec2 pin_application_point{Vec2::Zero()};   ///< Q_P [m]
  Vec2 bush_application_point{Vec2::Zero()};  ///< Q_B [m]
  double moment_on_pin{0.0};                  ///< about the pin centre p_WP [N·m]
  double moment_on_bush{0.0};                 ///< about the bush centre p_WB [N·m]
};

ContactLoads CalcContactLoads(const ContactGeometry& geometry, const ClearanceKinematics& kin,
                              double normal_force, double friction_force);

}  // namespace flexrod::contact
