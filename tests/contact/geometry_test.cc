// tests/contact/geometry_test.cc — clearance kinematics against direct calculations: the
// penetration and normal from positions, the normal rate and slip velocity against finite
// differences of moving material points, and the contact loads' balance and power.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "contact/geometry.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/error.h"

namespace flexrod::contact {
namespace {

const ContactGeometry kGeometry{10e-3, 9.5e-3, 12e-3};  // c = 0.5 mm

ClearanceMotion SampleMotion() {
  ClearanceMotion m;
  m.bush_centre = Vec2(0.10, -0.02);
  m.bush_velocity = Vec2(0.8, -0.3);
  m.bush_angular_velocity = 12.0;
  // Pin centre 0.52 mm from the bush centre at 30°: 20 µm penetration.
  m.pin_centre = m.bush_centre + 0.52e-3 * Vec2(std::cos(0.5236), std::sin(0.5236));
  m.pin_velocity = Vec2(0.5, 0.4);
  m.pin_angular_velocity = -7.0;
  return m;
}

Vec2 Rotate(const Vec2& v, double angle) {
  return Vec2(std::cos(angle) * v.x() - std::sin(angle) * v.y(),
              std::sin(angle) * v.x() + std::cos(angle) * v.y());
}

TEST(ClearanceKinematics, PenetrationIsEccentricityMinusClearance) {
  const ClearanceMotion m = SampleMotion();
  const ClearanceKinematics k = CalcClearanceKinematics(kGeometry, m);
  EXPECT_NEAR(k.eccentricity_norm, 0.52e-3, 1e-15);
  EXPECT_NEAR(k.penetration, 0.02e-3, 1e-15);
  EXPECT_NEAR(k.normal.norm(), 1.0, 1e-15);
  EXPECT_NEAR(k.normal.x(), std::cos(0.5236), 1e-12);
  EXPECT_NEAR(k.normal.dot(k.tangent), 0.0, 1e-15);
  EXPECT_NEAR(k.normal.x() * k.tangent.y() - k.normal.y() * k.tangent.x(), 1.0, 1e-15);
  EXPECT_TRUE(k.normal_defined);
  // The contact points: bush wall and the pin's outermost point along n; their distance along n
  // is the penetration.
  EXPECT_NEAR((k.pin_contact_point - k.bush_contact_point).dot(k.normal), k.penetration, 1e-15);
}

TEST(ClearanceKinematics, NormalRateIsTheTimeDerivativeOfEccentricity) {
  const ClearanceMotion m = SampleMotion();
  const double h = 1e-7;
  ClearanceMotion plus = m, minus = m;
  plus.pin_centre += h * m.pin_velocity;
  plus.bush_centre += h * m.bush_velocity;
  minus.pin_centre -= h * m.pin_velocity;
  minus.bush_centre -= h * m.bush_velocity;
  const double fd = (CalcClearanceKinematics(kGeometry, plus).penetration -
                     CalcClearanceKinematics(kGeometry, minus).penetration) /
                    (2 * h);
  EXPECT_NEAR(CalcClearanceKinematics(kGeometry, m).penetration_rate, fd, 1e-7);
}

TEST(ClearanceKinematics, SlipVelocityIsTheRelativeVelocityOfTheTouchingMaterialPoints) {
  // Move both rigid bodies for ±h and difference the positions of the material points that sit
  // at the contact points now (translation + rotation about each centre).
  const ClearanceMotion m = SampleMotion();
  const ClearanceKinematics k = CalcClearanceKinematics(kGeometry, m);
  const double h = 1e-7;
  auto material_point = [&](const Vec2& centre, const Vec2& velocity, double omega,
                            const Vec2& point, double dt) {
    return Vec2(centre + velocity * dt + Rotate(point - centre, omega * dt));
  };
  const Vec2 pin_v = (material_point(m.pin_centre, m.pin_velocity, m.pin_angular_velocity,
                                     k.pin_contact_point, h) -
                      material_point(m.pin_centre, m.pin_velocity, m.pin_angular_velocity,
                                     k.pin_contact_point, -h)) /
                     (2 * h);
  const Vec2 bush_v = (material_point(m.bush_centre, m.bush_velocity, m.bush_angular_velocity,
                                      k.bush_contact_point, h) -
                       material_point(m.bush_centre, m.bush_velocity, m.bush_angular_velocity,
                                      k.bush_contact_point, -h)) /
                      (2 * h);
  EXPECT_NEAR((k.relative_velocity - (pin_v - bush_v)).norm(), 0.0, 1e-8);
  EXPECT_NEAR(k.slip_velocity, k.tangent.dot(pin_v - bush_v), 1e-8);
  // Pure rotation of both bodies about coincident centres: v_t = ω_P R_P − ω_B R_B.
  ClearanceMotion spin;
  spin.pin_centre = Vec2(0.6e-3, 0.0);
  spin.pin_angular_velocity = 3.0;
  spin.bush_angular_velocity = 1.0;
  EXPECT_NEAR(CalcClearanceKinematics(kGeometry, spin).slip_velocity,
              3.0 * kGeometry.pin_radius - 1.0 * kGeometry.bush_radius, 1e-15);
}

TEST(ContactLoads, AreEqualAndOppositeWithFrictionMomentsForceTimesRadius) {
  const ClearanceMotion m = SampleMotion();
  const ClearanceKinematics k = CalcClearanceKinematics(kGeometry, m);
  const double fn = 1500.0, ft = -270.0;
  const ContactLoads loads = CalcContactLoads(kGeometry, k, fn, ft);
  EXPECT_NEAR((loads.force_on_pin + loads.force_on_bush).norm(), 0.0, 1e-12);
  EXPECT_NEAR(loads.force_on_pin.dot(k.normal), -fn, 1e-9);  // pushes the pin back inwards
  EXPECT_NEAR(loads.force_on_pin.dot(k.tangent), ft, 1e-9);
  auto cross = [](const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); };
  EXPECT_NEAR(loads.moment_on_pin,
              cross(loads.pin_application_point - m.pin_centre, loads.force_on_pin), 1e-12);
  EXPECT_NEAR(loads.moment_on_bush,
              cross(loads.bush_application_point - m.bush_centre, loads.force_on_bush), 1e-12);
  EXPECT_NEAR(loads.moment_on_pin, kGeometry.pin_radius * ft, 1e-12);
  EXPECT_NEAR(loads.moment_on_bush, -kGeometry.bush_radius * ft, 1e-12);
}

TEST(ContactLoads, PowerIsMinusNormalForceTimesRatePlusFrictionTimesSlip) {
  // Power of the loads on both bodies (forces on centres + moments × ω) = −F_n δ̇ + F_t v_t;
  // friction opposing slip therefore always dissipates.
  const ClearanceMotion m = SampleMotion();
  const ClearanceKinematics k = CalcClearanceKinematics(kGeometry, m);
  const double fn = 800.0, ft = -0.2 * fn * (k.slip_velocity > 0 ? 1.0 : -1.0);
  const ContactLoads l = CalcContactLoads(kGeometry, k, fn, ft);
  const double power =
      l.force_on_pin.dot(m.pin_velocity) + l.moment_on_pin * m.pin_angular_velocity +
      l.force_on_bush.dot(m.bush_velocity) + l.moment_on_bush * m.bush_angular_velocity;
  EXPECT_NEAR(power, -fn * k.penetration_rate + ft * k.slip_velocity, 1e-9);
  EXPECT_LT(ft * k.slip_velocity, 0.0);
}

TEST(ClearanceKinematics, CoincidentCentresGiveAnOpenJointWithAFallbackNormal) {
  ClearanceMotion m;
  m.pin_centre = m.bush_centre;
  const ClearanceKinematics k = CalcClearanceKinematics(kGeometry, m);
  EXPECT_FALSE(k.normal_defined);
  EXPECT_NEAR(k.penetration, -kGeometry.clearance(), 1e-18);
  EXPECT_EQ(k.normal, Vec2(1.0, 0.0));
  EXPECT_TRUE(std::isfinite(k.slip_velocity));
}

TEST(ContactGeometryInput, PinAsLargeAsTheBushIsRejected) {
  ContactGeometry g = kGeometry;
  g.pin_radius = g.bush_radius;
  try {
    g.Validate();
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "contact.pin_radius");
    EXPECT_NE(e.rule().find("clearance"), std::string::npos);
  }
  g = kGeometry;
  g.length = 0.0;
  EXPECT_THROW(g.Validate(), InputError);
  EXPECT_NO_THROW(kGeometry.Validate());
}

}  // namespace
}  // namespace flexrod::contact
