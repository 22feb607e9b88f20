// multibody/driver.cc — the drivers' own laws: DC motor parameters, speed profiles, the
// prescribed angle, speed and acceleration, the motor's torque line.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "multibody/mechanism.h"

namespace flexrod::multibody {

const char* ToString(DriverKind kind) {
  switch (kind) {
    case DriverKind::kConstantSpeed:
      return "constant-speed";
    case DriverKind::kSpeedProfile:
      return "speed-profile";
    case DriverKind::kDcMotor:
      return "dc-motor";
  }
  return "?";
}

void DcMotorSpec::Validate(const std::string& key) const {
  RequirePositive(key + ".stall_torque", stall_torque);
  RequirePositive(key + ".no_load_speed", no_load_speed);
  RequirePositive(key + ".ratio", ratio);
  RequireNonNegative(key + ".flywheel_inertia", flywheel_inertia);
  RequireNonNegative(key + ".rotor_inertia", rotor_inertia);
}

double SpeedProfile::Speed(double t) const {
  if (t <= times.front()) return speeds.front();
  if (t >= times.back()) return speeds.back();
  const auto k =
      static_cast<size_t>(std::upper_bound(times.begin(), times.end(), t) - times.begin()) - 1;
  const double slope = (speeds[k + 1] - speeds[k]) / (times[k + 1] - times[k]);
  return speeds[k] + slope * (t - times[k]);
}

double SpeedProfile::Acceleration(double t) const {
  if (t < times.front() || t >= times.back()) return 0.0;
  const auto k =
      static_cast<size_t>(std::upper_bound(times.begin(), times.end(), t) - times.begin()) - 1;
  return (speeds[k + 1] - speeds[k]) / (times[k + 1] - times[k]);
}

double SpeedProfile::Integral(double t) const {
  // F(t) = ∫_{t_0}^t ω ds, exact for the piecewise-linear ω; result F(t) − F(0).
  auto F = [this](double s) {
    if (s <= times.front()) return speeds.front() * (s - times.front());
    if (s >= times.back()) return cumulative.back() + speeds.back() * (s - times.back());
    const auto k =
        static_cast<size_t>(std::upper_bound(times.begin(), times.end(), s) - times.begin()) - 1;
    const double slope = (speeds[k + 1] - speeds[k]) / (times[k + 1] - times[k]);
    const double ds = s - times[k];
    return cumulative[k] + speeds[k] * ds + 0.5 * slope * ds * ds;
  };
  return F(t) - F(0.0);
}

double Driver::PrescribedAngle(double t) const {
  if (kind == DriverKind::kConstantSpeed) return initial_angle + speed * t;
  return initial_angle + profile.Integral(t);
}

double Driver::PrescribedSpeed(double t) const {
  if (kind == DriverKind::kConstantSpeed) return speed;
  return profile.Speed(t);
}

double Driver::PrescribedAcceleration(double t) const {
  if (kind == DriverKind::kConstantSpeed) return 0.0;
  return profile.Acceleration(t);
}

double Driver::MotorTorque(double body_speed) const {
  return motor.ratio * motor.stall_torque * (1.0 - motor.ratio * body_speed / motor.no_load_speed);
}

double Driver::MotorTorqueSlope() const {
  return -motor.ratio * motor.ratio * motor.stall_torque / motor.no_load_speed;
}

}  // namespace flexrod::multibody
