// SPDX-License-Identifier: GPL-3.0-or-later
// Linearised modes of an assembled mechanism (CalcMechanismModes) and the body damping matrix
// that gives them prescribed ratios (ModalDampingForBody, DampingSpec::Matrix).
#include "multibody/mechanism_modes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/error.h"
#include "mb_test_util.h"
#include "multibody/dae.h"
#include "multibody/run_data.h"

namespace flexrod::multibody {
namespace {

using testing::BuildFlexibleSliderCrank;
using testing::MakeSteelRod;
using testing::Record;
using testing::SliderCrankGuess;
using testing::SliderCrankParams;

constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// Two sliders on guides along x, ground –k1– slider 1 –k2– slider 2, springs at their free
/// lengths (no preload, so no lateral stiffness).
struct TwoSliders {
  double m1{2.0}, m2{0.5}, k1{800.0}, k2{300.0}, L1{0.3}, L2{0.2};
  Mechanism model;
  BodyId s1, s2;
  TwoSliders() {
    MechanismBuilder b;
    s1 = b.AddRigidBody({"s1", m1, 0.0, Vec2::Zero()});
    s2 = b.AddRigidBody({"s2", m2, 0.0, Vec2::Zero()});
    const MarkerId anchor = b.AddGroundMarker("anchor", Vec2::Zero());
    const MarkerId a1 = b.AddBodyMarker(s1, "s1.centre", Vec2::Zero());
    const MarkerId a2 = b.AddBodyMarker(s2, "s2.centre", Vec2::Zero());
    for (const auto& [name, slider] : {std::pair{"guide1", a1}, std::pair{"guide2", a2}}) {
      PrismaticSpec ps;
      ps.name = name;
      ps.marker_i = b.AddGroundMarker(std::string(name) + ".axis", Vec2::Zero());
      ps.marker_j = slider;
      b.AddPrismatic(ps);
    }
    b.AddSpringDamper("k1", anchor, a1, k1, 0.0, L1);
    b.AddSpringDamper("k2", a1, a2, k2, 0.0, L2);
    model = b.Build();
  }
  Vec RestPose() const {
    Vec p = Vec::Zero(model.num_coordinates());
    p[model.coordinate(s1, kX)] = L1;
    p[model.coordinate(s2, kX)] = L1 + L2;
    return p;
  }
};

// M = diag(m1, m2), K = [[k1 + k2, −k2], [−k2, k2]]: ω² are the roots of
// m1 m2 ω⁴ − (m1 k2 + m2 (k1 + k2)) ω² + k1 k2 = 0. The springs' stiffness comes from the
// force elements' finite-difference Jacobian (step cbrt(ε): ~1e-10 relative).
TEST(MechanismModes, TwoSpringMassChainHasTheAnalyticFrequencies) {
  const TwoSliders s;
  const MechanismModes modes = CalcMechanismModes(s.model, s.RestPose(), {});
  ASSERT_EQ(modes.num_modes(), 2);
  const double a = s.m1 * s.m2, b = -(s.m1 * s.k2 + s.m2 * (s.k1 + s.k2)), c = s.k1 * s.k2;
  const double disc = std::sqrt(b * b - 4.0 * a * c);
  const double w1 = std::sqrt((-b - disc) / (2.0 * a)), w2 = std::sqrt((-b + disc) / (2.0 * a));
  EXPECT_NEAR(modes.frequencies_hz(0), w1 / kTwoPi, 1e-8 * w1);
  EXPECT_NEAR(modes.frequencies_hz(1), w2 / kTwoPi, 1e-8 * w2);
  // M-normalised, and moving along the guides only.
  RunData data(s.model);
  Mat M;
  CalcMassMatrix(s.model, &data, s.RestPose(), &M);
  const Mat PtMP = modes.shapes.transpose() * M * modes.shapes;
  EXPECT_LT((PtMP - Mat::Identity(2, 2)).cwiseAbs().maxCoeff(), 1e-12);
  for (const BodyId body : {s.s1, s.s2}) {
    EXPECT_LT(modes.shapes.row(s.model.coordinate(body, kY)).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT(modes.shapes.row(s.model.coordinate(body, kTheta)).cwiseAbs().maxCoeff(), 1e-12);
  }
}

// Holding slider 1 leaves slider 2 on spring k2: ω = √(k2/m2). Holding a coordinate that a
// joint already holds (slider 1's y) is redundant and changes nothing.
TEST(MechanismModes, HeldCoordinatesAreFixedAndRedundantOnesAreHarmless) {
  const TwoSliders s;
  const int x1 = s.model.coordinate(s.s1, kX), y1 = s.model.coordinate(s.s1, kY);
  const MechanismModes modes = CalcMechanismModes(s.model, s.RestPose(), {x1, y1});
  ASSERT_EQ(modes.num_modes(), 1);
  const double w = std::sqrt(s.k2 / s.m2);
  EXPECT_NEAR(modes.frequencies_hz(0), w / kTwoPi, 1e-8 * w);
  EXPECT_LT(std::abs(modes.shapes(x1, 0)), 1e-12);
  EXPECT_THROW(CalcMechanismModes(s.model, s.RestPose(), {s.model.num_coordinates()}), InputError);
}

Mechanism BuildClampedRod(std::shared_ptr<const fem::ReducedRod> rod, DampingSpec damping,
                          BodyId* body) {
  MechanismBuilder b;
  FlexibleBodySpec fs;
  fs.name = "rod";
  fs.rod = std::move(rod);
  fs.damping = std::move(damping);
  *body = b.AddFlexibleBody(fs);
  b.AddGroundJoint("clamp", *body, Vec2(0.1, -0.05), 0.3);
  return b.Build();
}

Vec ClampedPose(const Mechanism& m, BodyId body) {
  Vec p = Vec::Zero(m.num_coordinates());
  SetBodyPose(m, body, Vec2(0.1, -0.05), 0.3, &p);
  return p;
}

// A flexible body whose frame is grounded is the rod clamped to its frame: its mechanism
// modes are the body's own modes of (K, M_ff), and the matrix that gives them ratios ζ is the
// clamped-frame modal damping M_ff Φ diag(2ζω) Φᵀ M_ff (DampingSpec::ModalRatio).
TEST(MechanismModes, FlexibleBodyClampedInTheWorldHasItsOwnModes) {
  auto rod = MakeSteelRod(0.25, 20, 6);
  BodyId body;
  const Mechanism m = BuildClampedRod(rod, DampingSpec::None(), &body);
  const int n = m.body(body).num_modes;
  const MechanismModes modes = CalcMechanismModes(m, ClampedPose(m, body), {});
  ASSERT_EQ(modes.num_modes(), n);
  const Vec& own = m.body(body).modal_frequencies_hz;
  for (int i = 0; i < n; ++i) EXPECT_NEAR(modes.frequencies_hz(i), own(i), 1e-9 * own(i)) << i;
  // The frame does not move in any mode.
  EXPECT_LT(modes.shapes.topRows(3).cwiseAbs().maxCoeff(), 1e-12);

  constexpr double kZeta = 0.03;
  const Mat D = ModalDampingForBody(m, modes, body, Vec::Constant(n, kZeta));
  BodyId clamped;
  const Mechanism old = BuildClampedRod(rod, DampingSpec::ModalRatio({kZeta}), &clamped);
  const Mat& D_clamped = old.body(clamped).D;
  EXPECT_LT((D - D_clamped).cwiseAbs().maxCoeff(), 1e-10 * D_clamped.cwiseAbs().maxCoeff());
}

struct FlexibleCrank {
  SliderCrankParams P;
  testing::SliderCrankModel sc;
  Vec p;  ///< assembled configuration at θ0
  FlexibleCrank(DampingSpec damping = DampingSpec::None())
      : sc(BuildFlexibleSliderCrank(P, MakeSteelRod(P.l, 20, 4), std::move(damping))) {
    RunData data(sc.model);
    const ConsistentState s = ComputeConsistentState(sc.model, &data, 0.0, SliderCrankGuess(sc, P));
    p = s.y.head(sc.model.num_coordinates());
  }
  MechanismModes Modes() const {
    return CalcMechanismModes(sc.model, p, {sc.model.coordinate(sc.crank, kTheta)});
  }
};

/// Ψᵀ D_full Ψ for body `body`'s damping D embedded in the q–q block.
Mat ModalDamping(const Mechanism& m, const MechanismModes& modes, BodyId body, const Mat& D) {
  const int n = m.body(body).num_modes, q0 = m.coordinate(body, kFirstMode);
  const Mat Q = modes.shapes.middleRows(q0, n);
  return Q.transpose() * D * Q;
}

// In the slider-crank with the crank held (its driver holds it too: a redundant row), the
// rod's elastic coordinates parametrise the motion: one mechanism mode per coordinate. The
// matrix from ModalDampingForBody makes the modal damping matrix exactly diag(2 ζ_i ω_i); the
// clamped-frame modal damping does not (it over-damps the mechanism's modes, and couples them).
TEST(MechanismModes, ModalDampingForBodyDiagonalisesTheMechanismsModalDamping) {
  const FlexibleCrank fc;
  const Mechanism& m = fc.sc.model;
  const BodyId rod = fc.sc.rod;
  const int n = m.body(rod).num_modes;
  const MechanismModes modes = fc.Modes();
  ASSERT_EQ(modes.num_modes(), n);
  EXPECT_GT(modes.frequencies_hz(0), 0.0);
  Vec zeta(n);
  for (int i = 0; i < n; ++i) zeta(i) = 0.01 * (i + 1);
  const Mat D = ModalDampingForBody(m, modes, rod, zeta);
  const Vec omega = kTwoPi * modes.frequencies_hz;
  const Mat want = (2.0 * zeta.cwiseProduct(omega)).asDiagonal();
  const Mat got = ModalDamping(m, modes, rod, D);
  EXPECT_LT((got - want).cwiseAbs().maxCoeff(), 1e-10 * want.cwiseAbs().maxCoeff());
  EXPECT_LT((D - D.transpose()).cwiseAbs().maxCoeff(), 1e-14 * D.cwiseAbs().maxCoeff());

  // The matrix reaches the body unchanged through DampingSpec::Matrix.
  const FlexibleCrank with_matrix(DampingSpec::Matrix(D));
  const Mat& D_body = with_matrix.sc.model.body(with_matrix.sc.rod).D;
  EXPECT_LT((D_body - D).cwiseAbs().maxCoeff(), 1e-15 * D.cwiseAbs().maxCoeff());
  EXPECT_EQ(with_matrix.sc.model.body(with_matrix.sc.rod).modal_damping_ratios.size(), 0);

  // The clamped-frame damping (2 % of the body's own modes) gives mode 1 of the mechanism more.
  const FlexibleCrank clamped(DampingSpec::ModalRatio({0.02}));
  const Mat old = ModalDamping(m, modes, rod, clamped.sc.model.body(clamped.sc.rod).D);
  const double zeta1 = old(0, 0) / (2.0 * omega(0));
  Record("clamped_frame_zeta_mode1", zeta1);
  EXPECT_GT(std::abs(zeta1 - 0.02), 0.05 * 0.02);
}

TEST(MechanismModes, ModalDampingForBodyNeedsOneInvertibleModePerCoordinate) {
  auto rod = MakeSteelRod(0.25, 20, 4);
  BodyId body;
  const Mechanism m = BuildClampedRod(rod, DampingSpec::None(), &body);
  const int n = m.body(body).num_modes;
  const MechanismModes modes = CalcMechanismModes(m, ClampedPose(m, body), {});
  MechanismModes fewer;
  fewer.frequencies_hz = modes.frequencies_hz.head(n - 1);
  fewer.shapes = modes.shapes.leftCols(n - 1);
  EXPECT_THROW(ModalDampingForBody(m, fewer, body, Vec::Constant(n - 1, 0.02)), NumericalError);
  MechanismModes repeated = modes;
  repeated.shapes.col(1) = repeated.shapes.col(0);
  EXPECT_THROW(ModalDampingForBody(m, repeated, body, Vec::Constant(n, 0.02)), NumericalError);
  EXPECT_THROW(ModalDampingForBody(m, modes, body, Vec::Constant(n, -0.02)), InputError);
}

TEST(DampingMatrix, ValidateNamesTheKeyForBadMatrices) {
  auto rod = MakeSteelRod(0.25, 20, 4);
  const int n = rod->num_coordinates();
  auto build = [&](Mat d) {
    BodyId body;
    BuildClampedRod(rod, DampingSpec::Matrix(std::move(d)), &body);
  };
  auto expect_key = [&](Mat d) {
    try {
      build(std::move(d));
      ADD_FAILURE() << "no InputError";
    } catch (const InputError& e) {
      EXPECT_EQ(e.key(), "body[rod].damping.matrix") << e.what();
    }
  };
  expect_key(Mat::Identity(n - 1, n - 1));
  Mat asym = Mat::Identity(n, n);
  asym(0, 1) = 1e-3;
  expect_key(asym);
  expect_key(-Mat::Identity(n, n));
  Mat nan = Mat::Identity(n, n);
  nan(1, 1) = std::nan("");
  expect_key(nan);
  EXPECT_NO_THROW(build(Mat::Zero(n, n)));
  EXPECT_NO_THROW(build(Mat::Identity(n, n)));
}

}  // namespace
}  // namespace flexrod::multibody
