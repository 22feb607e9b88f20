// tests/multibody/builder_test.cc — bad input is rejected before any work starts, with an
// InputError naming the key, the value and the rule; the built model has the documented
// layout and readable variable names.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <stdexcept>

#include "common/error.h"
#include "mb_test_util.h"
#include "multibody/mechanism.h"
#include "multibody/simulate.h"

namespace flexrod::multibody {
namespace {

// Runs f, expects an InputError whose key contains `key`.
template <typename F>
void ExpectInputError(F f, const std::string& key) {
  try {
    f();
    ADD_FAILURE() << "no InputError for " << key;
  } catch (const InputError& e) {
    EXPECT_NE(e.key().find(key), std::string::npos) << "key was " << e.key() << ": " << e.what();
    EXPECT_FALSE(e.rule().empty());
  }
}

TEST(MechanismBuilder, RejectsNonPositiveMassNamingTheBody) {
  MechanismBuilder b;
  ExpectInputError([&] { b.AddRigidBody({"crank", -1.0, 0.1, Vec2::Zero()}); }, "body[crank].mass");
}

TEST(MechanismBuilder, RejectsDuplicateNames) {
  MechanismBuilder b;
  b.AddRigidBody({"a", 1.0, 0.1, Vec2::Zero()});
  ExpectInputError([&] { b.AddRigidBody({"a", 1.0, 0.1, Vec2::Zero()}); }, "body.name");
}

TEST(MechanismBuilder, RejectsAJointBetweenTwoMarkersOfOneBody) {
  MechanismBuilder b;
  const BodyId a = b.AddRigidBody({"a", 1.0, 0.1, Vec2::Zero()});
  const MarkerId m1 = b.AddBodyMarker(a, "a.1", Vec2(0.0, 0.0));
  const MarkerId m2 = b.AddBodyMarker(a, "a.2", Vec2(1.0, 0.0));
  ExpectInputError([&] { b.AddRevolute("j", m1, m2); }, "joint[j].markers");
}

TEST(MechanismBuilder, RejectsTwoDriversOnOneBody) {
  MechanismBuilder b;
  const BodyId a = b.AddRigidBody({"a", 1.0, 0.1, Vec2::Zero()});
  b.AddConstantSpeedDriver("d1", a, 0.0, 1.0);
  b.AddConstantSpeedDriver("d2", a, 0.0, 2.0);
  ExpectInputError([&] { b.Build(); }, "driver[d2].body");
}

TEST(MechanismBuilder, RejectsABodyThatIsGroundedAndDriven) {
  MechanismBuilder b;
  const BodyId a = b.AddRigidBody({"a", 1.0, 0.1, Vec2::Zero()});
  b.AddGroundJoint("g", a, Vec2::Zero(), 0.0);
  b.AddConstantSpeedDriver("d", a, 0.0, 1.0);
  ExpectInputError([&] { b.Build(); }, "joint[g].body");
}

TEST(MechanismBuilder, RejectsNodeMarkersOnRigidBodies) {
  MechanismBuilder b;
  const BodyId a = b.AddRigidBody({"a", 1.0, 0.1, Vec2::Zero()});
  ExpectInputError([&] { b.AddNodeMarker(a, "m", 0); }, "marker[m].body");
}

TEST(MechanismBuilder, RejectsModalRatiosOfTheWrongCount) {
  MechanismBuilder b;
  FlexibleBodySpec s;
  s.name = "rod";
  s.rod = testing::MakeSyntheticRod(4, 10, 1);
  s.damping = DampingSpec::ModalRatio({0.01, 0.02});
  ExpectInputError([&] { b.AddFlexibleBody(s); }, "body[rod].damping.modal_ratios");
}

TEST(MechanismBuilder, RejectsAFlexibleBodyWithoutRod) {
  MechanismBuilder b;
  FlexibleBodySpec s;
  s.name = "rod";
  ExpectInputError([&] { b.AddFlexibleBody(s); }, "body[rod].rod");
}

TEST(MechanismBuilder, RejectsASpeedProfileWithNonIncreasingTimes) {
  MechanismBuilder b;
  const BodyId a = b.AddRigidBody({"a", 1.0, 0.1, Vec2::Zero()});
  ExpectInputError(
      [&] {
        b.AddSpeedProfileDriver("p", a, 0.0, {0.0, 1.0, 1.0}, {1.0, 2.0, 3.0});
      },
      "driver[p].times[2]");
}

TEST(MechanismBuilder, RejectsAnOverConstrainedModel) {
  MechanismBuilder b;
  const BodyId a = b.AddRigidBody({"a", 1.0, 0.1, Vec2::Zero()});
  const MarkerId g1 = b.AddGroundMarker("g1", Vec2(0.0, 0.0));
  const MarkerId g2 = b.AddGroundMarker("g2", Vec2(1.0, 0.0));
  const MarkerId m1 = b.AddBodyMarker(a, "a.1", Vec2(0.0, 0.0));
  const MarkerId m2 = b.AddBodyMarker(a, "a.2", Vec2(1.0, 0.0));
  b.AddRevolute("r1", g1, m1);
  b.AddRevolute("r2", g2, m2);  // 4 equations for 3 coordinates
  ExpectInputError([&] { b.Build(); }, "mechanism.constraints");
}

TEST(MechanismBuilder, CannotBeUsedAfterBuild) {
  MechanismBuilder b;
  b.AddRigidBody({"a", 1.0, 0.1, Vec2::Zero()});
  b.Build();
  EXPECT_THROW(b.AddRigidBody({"b", 1.0, 0.1, Vec2::Zero()}), std::logic_error);
}

TEST(MechanismBuilder, RejectsNegativeSpringStiffness) {
  MechanismBuilder b;
  const BodyId a = b.AddRigidBody({"a", 1.0, 0.1, Vec2::Zero()});
  const MarkerId g = b.AddGroundMarker("g", Vec2(0.0, 0.0));
  const MarkerId m = b.AddBodyMarker(a, "a.m", Vec2(0.0, 0.0));
  ExpectInputError([&] { b.AddSpringDamper("s", g, m, -5.0, 0.0, 0.1); }, "element[s].stiffness");
}

TEST(Mechanism, LayoutAndVariableNamesFollowTheDocumentedOrder) {
  testing::SliderCrankParams P;
  const auto sc = testing::BuildRigidSliderCrank(P);
  const Mechanism& m = sc.model;
  EXPECT_EQ(m.num_coordinates(), 9);
  EXPECT_EQ(m.num_constraints(), 9);  // 3 revolute × 2 + prismatic 2 + driver 1
  EXPECT_EQ(m.size(), 2 * 9 + 2 * 9 + kNumQuadratures);
  EXPECT_EQ(m.VariableName(m.coordinate(sc.rod, kTheta)), "p[rod.theta]");
  EXPECT_EQ(m.VariableName(m.v_offset() + m.coordinate(sc.slider, kX)), "v[slider.x]");
  EXPECT_EQ(m.VariableName(m.lambda_offset() + m.joint(sc.guide).row + 1), "lambda[guide.1]");
  EXPECT_EQ(m.VariableName(m.mu_offset() + m.driver(sc.driver).row), "mu[motor]");
  EXPECT_EQ(m.VariableName(m.quadrature_offset() + kDriverWork), "energy[driver_work]");
  EXPECT_EQ(m.FindBody("rod").index, sc.rod.index);
  ExpectInputError([&] { m.FindMarker("nope"); }, "marker");
}

TEST(SimulationOptions, RejectsAnEndTimeBeforeTheStart) {
  testing::SliderCrankParams P;
  const auto sc = testing::BuildRigidSliderCrank(P);
  SimulationOptions opt;
  opt.t_start = 1.0;
  opt.t_end = 0.5;
  ExpectInputError([&] { opt.Validate(sc.model); }, "simulation.t_end");
  opt.t_end = 2.0;
  opt.integrator.rel_tol = 0.0;
  ExpectInputError([&] { opt.Validate(sc.model); }, "integrator.rel_tol");
  opt.integrator.rel_tol = 1e-6;
  opt.start_sampling_at_index = true;
  ExpectInputError([&] { opt.Validate(sc.model); }, "simulation.start_sampling_at_index");
}

}  // namespace
}  // namespace flexrod::multibody
