// contact/geometry.cc — clearance-joint kinematics and contact loads (see geometry.h).
// SPDX-License-Identifier: GPL-3.0-or-later
#include "contact/geometry.h"

#include <cmath>

#include "common/error.h"

namespace flexrod::contact {

void ContactGeometry::Validate() const {
  if (!(std::isfinite(pin_radius) && pin_radius > 0.0)) {
    throw InputError("contact.pin_radius", FormatValue(pin_radius) + " m",
                     "must be finite and > 0");
  }
  if (!(std::isfinite(bush_radius) && bush_radius > 0.0)) {
    throw InputError("contact.bush_radius", FormatValue(bush_radius) + " m",
                     "must be finite and > 0");
  }
  if (!(pin_radius < bush_radius)) {
    throw InputError("contact.pin_radius", FormatValue(pin_radius) + " m",
                     "must be < bush_radius = " + FormatValue(bush_radius) +
                         " m (the radial clearance R_bush - R_pin must be > 0)");
  }
  if (!(std::isfinite(length) && length > 0.0)) {
    throw InputError("contact.length", FormatValue(length) + " m", "must be finite and > 0");
  }
}

ClearanceKinematics CalcClearanceKinematics(const ContactGeometry& geometry,
                                            const ClearanceMotion& motion) {
  ClearanceKinematics k;
  k.eccentricity = motion.pin_centre - motion.bush_centre;
  k.eccentricity_norm = k.eccentricity.norm();
  k.penetration = k.eccentricity_norm - geometry.clearance();
  k.normal_defined = k.eccentricity_norm >= kMinEccentricity;
  k.normal = k.normal_defined ? Vec2(k.eccentricity / k.eccentricity_norm) : Vec2(1.0, 0.0);
  k.tangent = Vec2(-k.normal.y(), k.normal.x());

  const Vec2 dv = motion.pin_velocity - motion.bush_velocity;
  k.penetration_rate = k.normal.dot(dv);
  k.bush_contact_point = motion.bush_centre + geometry.bush_radius * k.normal;
  k.pin_contact_point = motion.pin_centre + geometry.pin_radius * k.normal;
  // Velocity of a material point at r from a body's centre: v + ω × r; with r = R n this is
  // v + ω R t in 2-D.
  const Vec2 pin_point_velocity =
      motion.pin_velocity + motion.pin_angular_velocity * geometry.pin_radius * k.tangent;
  const Vec2 bush_point_velocity =
      motion.bush_velocity + motion.bush_angular_velocity * geometry.bush_radius * k.tangent;
  k.relative_velocity = pin_point_velocity - bush_point_velocity;
  k.slip_velocity = k.tangent.dot(k.relative_velocity);
  return k;
}

ContactLoads CalcContactLoads(const ContactGeometry& geometry, const ClearanceKinematics& kin,
                              double normal_force, double friction_force) {
  ContactLoads loads;
  loads.force_on_pin = -normal_force * kin.normal + friction_force * kin.tangent;
  loads.force_on_bush = -loads.force_on_pin;
  loads.pin_application_point = kin.pin_contact_point;
  loads.bush_application_point = kin.bush_contact_point;
  // n × t = 1 for t = n rotated by +90°.
  loads.moment_on_pin = geometry.pin_radius * friction_force;
  loads.moment_on_bush = -geometry.bush_radius * friction_force;
  return loads;
}

}  // namespace flexrod::contact
