// SPDX-License-Identifier: GPL-3.0-or-later
#include "common/units.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>
#include <string_view>

#include "common/error.h"

namespace flexrod {
namespace {

struct UnitDef {
  std::string_view symbol;
  Dimension dim;
  double to_si;
};

constexpr double kPi = std::numbers::pi;
constexpr double kInch = 0.0254;  // m, exact by definition

constexpr UnitDef kUnits[] = {
    {"m", Dimension::kLength, 1.0},
    {"mm", Dimension::kLength, 1e-3},
    {"cm", Dimension::kLength, 1e-2},
    {"um", Dimension::kLength, 1e-6},
    {"in", Dimension::kLength, kInch},
    {"kg", Dimension::kMass, 1.0},
    {"g", Dimension::kMass, 1e-3},
    {"s", Dimension::kTime, 1.0},
    {"ms", Dimension::kTime, 1e-3},
    {"us", Dimension::kTime, 1e-6},
    {"Hz", Dimension::kFrequency, 1.0},
    {"kHz", Dimension::kFrequency, 1e3},
    {"rad", Dimension::kAngle, 1.0},
    {"deg", Dimension::kAngle, kPi / 180.0},
    {"rad/s", Dimension::kAngularVelocity, 1.0},
    {"rpm", Dimension::kAngularVelocity, 2.0 * kPi / 60.0},
    {"deg/s", Dimension::kAngularVelocity, kPi / 180.0},
    {"m/s", Dimension::kVelocity, 1.0},
    {"mm/s", Dimension::kVelocity, 1e-3},
    {"m/s^2", Dimension::kAcceleration, 1.0},
    {"g0", Dimension::kAcceleration, 9.80665},
    {"N", Dimension::kForce, 1.0},
    {"kN", Dimension::kForce, 1e3},
    {"N*m", Dimension::kTorque, 1.0},
    {"Nm", Dimension::kTorque, 1.0},
    {"N m", Dimension::kTorque, 1.0},
    {"Pa", Dimension::kPressure, 1.0},
    {"kPa", Dimension::kPressure, 1e3},
    {"MPa", Dimension::kPressure, 1e6},
    {"GPa", Dimension::kPressure, 1e9},
    {"kg/m^3", Dimension::kDensity, 1.0},
    {"g/cm^3", Dimension::kDensity, 1e3},
    {"kg*m^2", Dimension::kInertia, 1.0},
    {"kg m^2", Dimension::kInertia, 1.0},
    {"N/m", Dimension::kStiffness, 1.0},
    {"N/mm", Dimension::kStiffness, 1e3},
    {"N*s/m", Dimension::kDamping, 1.0},
    {"N s/m", Dimension::kDamping, 1.0},
    {"N*m*s/rad", Dimension::kRotDamping, 1.0},
    {"N*m/rad", Dimension::kRotStiffness, 1.0},
    {"%", Dimension::kDimensionless, 1e-2},
};

std::string_view Trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

}  // namespace

const char* SiUnit(Dimension dim) {
  switch (dim) {
    case Dimension::kDimensionless:
      return "1";
    case Dimension::kLength:
      return "m";
    case Dimension::kMass:
      return "kg";
    case Dimension::kTime:
      return "s";
    case Dimension::kFrequency:
      return "Hz";
    case Dimension::kAngle:
      return "rad";
    case Dimension::kAngularVelocity:
      return "rad/s";
    case Dimension::kVelocity:
      return "m/s";
    case Dimension::kAcceleration:
      return "m/s^2";
    case Dimension::kForce:
      return "N";
    case Dimension::kTorque:
      return "N*m";
    case Dimension::kPressure:
      return "Pa";
    case Dimension::kDensity:
      return "kg/m^3";
    case Dimension::kInertia:
      return "kg*m^2";
    case Dimension::kStiffness:
      return "N/m";
    case Dimension::kDamping:
      return "N*s/m";
    case Dimension::kRotDamping:
      return "N*m*s/rad";
    case Dimension::kRotStiffness:
      return "N*m/rad";
    case Dimension::kAny:
      return "SI";
  }
  return "?";
}

double ParseQuantity(const std::string& key, const std::string& text, Dimension dim) {
  const std::string_view s = Trim(text);
  double value = 0.0;
  const char* begin = s.data();
  const char* end = s.data() + s.size();
  auto [ptr, ec] = std::from_chars(begin, end, value);
  if (ec != std::errc() || ptr == begin) {
    throw InputError(key, "\"" + text + "\"",
                     std::string("must be a number, optionally with a unit (") + SiUnit(dim) + ")");
  }
  if (!std::isfinite(value)) throw InputError(key, "\"" + text + "\"", "must be finite");
  const std::string_view unit = Trim(std::string_view(ptr, end - ptr));
  if (unit.empty()) return value;
  for (const UnitDef& u : kUnits) {
    if (u.symbol == unit) {
      if (dim != Dimension::kAny && u.dim != dim) {
        throw InputError(key, "\"" + text + "\"",
                         std::string("unit '") + std::string(unit) +
                             "' has the wrong dimension; expected " + SiUnit(dim));
      }
      return value * u.to_si;
    }
  }
  throw InputError(
      key, "\"" + text + "\"",
      "unknown unit '" + std::string(unit) + "'; expected " + SiUnit(dim) + " or a multiple");
}

double WrapToTwoPi(double angle) {
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  double w = std::fmod(angle, kTwoPi);
  if (w < 0.0) w += kTwoPi;
  return w >= kTwoPi ? 0.0 : w;  // round-off at the seam
}

}  // namespace flexrod
