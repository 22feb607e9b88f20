// common/units.h — conversion of user-facing quantities ("19.05 mm", "200 GPa", "250 rpm") to SI,
// done once, at the input boundary. Nothing inside flexrod uses non-SI units.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <string>

namespace flexrod {

/// Physical dimension a quantity must have; the parser rejects a unit of another dimension.
enum class Dimension {
  kDimensionless,
  kLength,           // m
  kMass,             // kg
  kTime,             // s
  kFrequency,        // Hz
  kAngle,            // rad
  kAngularVelocity,  // rad/s
  kVelocity,         // m/s
  kAcceleration,     // m/s^2
  kForce,            // N
  kTorque,           // N m
  kPressure,         // Pa
  kDensity,          // kg/m^3
  kInertia,          // kg m^2
  kStiffness,        // N/m
  kDamping,          // N s/m
  kRotDamping,       // N m s/rad
  kRotStiffness,     // N m/rad
  kAny,              // any known unit or a bare number
};

/// Parses "<number> [unit]" and returns the value in SI. A bare number is taken as SI.
/// Throws InputError naming `key` if the text is not a number, or the unit is unknown or of
/// another dimension.
double ParseQuantity(const std::string& key, const std::string& text, Dimension dim);

/// θ mod 2π in [0, 2π) [rad]: the exact remainder of the double (std::fmod), so an angle of
/// many turns keeps what its double carries.
double WrapToTwoPi(double angle);

/// The SI unit symbol for a dimension, for messages and column headers ("m", "Pa", ...).
const char* SiUnit(Dimension dim);

}  // namespace flexrod
