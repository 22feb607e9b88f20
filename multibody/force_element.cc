// multibody/force_element.cc — the built-in force elements.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "multibody/force_element.h"

#include <cmath>

#include "common/error.h"

namespace flexrod::multibody {
namespace {

// Below this distance the spring direction is undefined [m].
constexpr double kMinSpringLength = 1e-12;

double Cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

}  // namespace

SpringDamper::SpringDamper(const std::string& key, double stiffness, double damping,
                           double free_length)
    : stiffness_(stiffness), damping_(damping), free_length_(free_length) {
  RequireNonNegative(key + ".stiffness", stiffness);
  RequireNonNegative(key + ".damping", damping);
  RequireNonNegative(key + ".free_length", free_length);
}

bool SpringDamper::Evaluate(double /*t*/, const MarkerKinematics& i, const MarkerKinematics& j,
                            const double* /*z*/, const double* /*memory*/,
                            ElementOutput* out) const {
  const Vec2 d = j.position - i.position;
  const double length = d.norm();
  if (!(length > kMinSpringLength)) return false;
  const Vec2 e = d / length;
  const double rate = e.dot(j.velocity - i.velocity);
  const double tension = stiffness_ * (length - free_length_) + damping_ * rate;
  out->force_i = tension * e;
  out->force_j = -tension * e;
  out->dissipation = damping_ * rate * rate;
  return true;
}

double SpringDamper::PotentialEnergy(const MarkerKinematics& i, const MarkerKinematics& j,
                                     const double* /*z*/, const double* /*memory*/) const {
  const double stretch = (j.position - i.position).norm() - free_length_;
  return 0.5 * stiffness_ * stretch * stretch;
}

FiniteDifferenceScales SpringDamper::fd_scales() const {
  FiniteDifferenceScales s;
  s.length = std::max(1e-3, 1e-2 * free_length_);
  return s;
}

RotationalSpringDamper::RotationalSpringDamper(const std::string& key, double stiffness,
                                               double damping, double free_angle)
    : stiffness_(stiffness), damping_(damping), free_angle_(free_angle) {
  RequireNonNegative(key + ".stiffness", stiffness);
  RequireNonNegative(key + ".damping", damping);
  Require(std::isfinite(free_angle), key + ".free_angle", free_angle, "must be finite");
}

bool RotationalSpringDamper::Evaluate(double /*t*/, const MarkerKinematics& i,
                                      const MarkerKinematics& j, const double* /*z*/,
                                      const double* /*memory*/, ElementOutput* out) const {
  const double delta = j.angle - i.angle - free_angle_;
  const double rate = j.angular_velocity - i.angular_velocity;
  const double moment = stiffness_ * delta + damping_ * rate;
  out->moment_i = moment;
  out->moment_j = -moment;
  out->dissipation = damping_ * rate * rate;
  return true;
}

double RotationalSpringDamper::PotentialEnergy(const MarkerKinematics& i, const MarkerKinematics& j,
                                               const double* /*z*/,
                                               const double* /*memory*/) const {
  const double delta = j.angle - i.angle - free_angle_;
  return 0.5 * stiffness_ * delta * delta;
}

PrismaticGuide::PrismaticGuide(const std::string& key, const Vec2& axis, double damping,
                               double friction_force, double regularisation_speed)
    : damping_(damping),
      friction_force_(friction_force),
      regularisation_speed_(regularisation_speed) {
  Require(axis.norm() > 0.0, key + ".axis", axis.norm(), "must be a non-zero vector");
  axis_ = axis.normalized();
  RequireNonNegative(key + ".damping", damping);
  RequireNonNegative(key + ".friction_force", friction_force);
  RequirePositive(key + ".friction_regularisation_speed", regularisation_speed);
}

bool PrismaticGuide::Evaluate(double /*t*/, const MarkerKinematics& i, const MarkerKinematics& j,
                              const double* /*z*/, const double* /*memory*/,
                              ElementOutput* out) const {
  const double c = std::cos(i.angle), s = std::sin(i.angle);
  const Vec2 u(c * axis_.x() - s * axis_.y(), s * axis_.x() + c * axis_.y());
  const Vec2 d = j.position - i.position;
  // Sliding speed of point j relative to the material point of body i under it.
  const double slide = u.dot(j.velocity - i.velocity) - i.angular_velocity * Cross(d, u);
  const double f = damping_ * slide + friction_force_ * std::tanh(slide / regularisation_speed_);
  out->force_j = -f * u;
  out->force_i = f * u;
  out->moment_i = f * Cross(d, u);  // reaction acts at p_j, moved to marker i
  out->dissipation = f * slide;
  return true;
}

FiniteDifferenceScales PrismaticGuide::fd_scales() const {
  FiniteDifferenceScales s;
  s.speed = std::min(1e-3, regularisation_speed_);
  return s;
}

}  // namespace flexrod::multibody
