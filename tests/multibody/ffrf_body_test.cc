// tests/multibody/ffrf_body_test.cc — the floating-frame body kernels against an independent
// point-mass cloud (ffrf-planar.md "Checks that pin every term"): M(θ, q) is symmetric
// positive definite, ½ṗᵀMṗ and Q_v equal the sums over the cloud, Q_v satisfies the
// Lagrange identity Q_v = −Ṁṗ + ∂T/∂p, q = 0 reproduces mass, centre of mass and inertia,
// rigid bodies are the n = 0 case, and the modal damping has the prescribed ratios.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <random>

#include "common/error.h"
#include "mb_test_util.h"
#include "multibody/dae.h"
#include "multibody/mechanism.h"
#include "multibody/outputs.h"
#include "multibody/run_data.h"
#include "multibody/simulate.h"

namespace flexrod::multibody {
namespace {

using testing::Jmat;
using testing::MakeSyntheticRod;
using testing::PointCloud;

constexpr int kModes = 5;
constexpr int kPoints = 16;

struct Fixture {
  PointCloud cloud;
  std::shared_ptr<fem::ReducedRod> rod;
  Mechanism model;
  const Body& body() const { return model.bodies()[0]; }
};

Fixture Make(DampingSpec damping = DampingSpec::None()) {
  Fixture f;
  f.rod = MakeSyntheticRod(kModes, kPoints, 42, &f.cloud);
  MechanismBuilder b;
  FlexibleBodySpec s;
  s.name = "rod";
  s.rod = f.rod;
  s.damping = damping;
  s.geometric_stiffening = false;  // the linear FFRF equations of ffrf-planar.md
  b.AddFlexibleBody(s);
  f.model = b.Build();
  return f;
}

Mat2 Rot(double th) {
  Mat2 A;
  A << std::cos(th), -std::sin(th), std::sin(th), std::cos(th);
  return A;
}

Vec RandomVec(int n, std::mt19937& gen, double scale) {
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  Vec v(n);
  for (int i = 0; i < n; ++i) v(i) = scale * U(gen);
  return v;
}

// L_k = [I, A J ū_k, A S_k] for cloud point k (ffrf-planar.md "Kinematics").
Mat PointJacobian(const PointCloud& c, int k, const Vec& p) {
  const int n = static_cast<int>(p.size()) - 3;
  const Mat2 A = Rot(p(2));
  const Vec2 ubar = c.u0[k] + c.S[k] * p.tail(n);
  Mat L = Mat::Zero(2, 3 + n);
  L.block(0, 0, 2, 2).setIdentity();
  const Vec2 aju = A * (Jmat() * ubar);
  L(0, 2) = aju.x();
  L(1, 2) = aju.y();
  L.rightCols(n) = A * c.S[k];
  return L;
}

TEST(FfrfBody, MassMatrixIsSymmetricPositiveDefinite) {
  const Fixture f = Make();
  std::mt19937 gen(1);
  for (int trial = 0; trial < 20; ++trial) {
    Vec p = RandomVec(3 + kModes, gen, 1.0);
    p(2) *= 3.0;
    p.tail(kModes) *= 0.5;  // large deformations: still SPD
    const Mat M = BodyMassMatrix(f.body(), p);
    EXPECT_EQ((M - M.transpose()).cwiseAbs().maxCoeff(), 0.0);
    Eigen::SelfAdjointEigenSolver<Mat> es(M);
    EXPECT_GT(es.eigenvalues().minCoeff(), 0.0) << "trial " << trial;
  }
}

// T = ½ Σ m_k |L_k ṗ|² and Q_v = −Σ m_k L_kᵀ a_v,k with a_v = −Aū θ̇² + 2AJS q̇ θ̇: the cloud
// sums are exact, so agreement is to round-off (1e-12 relative).
TEST(FfrfBody, KineticEnergyAndQuadraticVelocityEqualThePointCloudSums) {
  const Fixture f = Make();
  std::mt19937 gen(2);
  for (int trial = 0; trial < 10; ++trial) {
    const Vec p = RandomVec(3 + kModes, gen, 1.0);
    const Vec v = RandomVec(3 + kModes, gen, 3.0);
    const Mat M = BodyMassMatrix(f.body(), p);
    const Vec Qv = BodyQuadraticVelocity(f.body(), p, v);
    double T_cloud = 0.0;
    Vec Qv_cloud = Vec::Zero(3 + kModes);
    const Mat2 A = Rot(p(2));
    for (int k = 0; k < kPoints; ++k) {
      const Mat L = PointJacobian(f.cloud, k, p);
      const Vec2 rdot = L * v;
      T_cloud += 0.5 * f.cloud.m[k] * rdot.squaredNorm();
      const Vec2 ubar = f.cloud.u0[k] + f.cloud.S[k] * p.tail(kModes);
      const Vec2 av =
          -A * ubar * v(2) * v(2) + 2.0 * A * Jmat() * f.cloud.S[k] * v.tail(kModes) * v(2);
      Qv_cloud -= f.cloud.m[k] * L.transpose() * av;
    }
    EXPECT_NEAR(0.5 * v.dot(M * v), T_cloud, 1e-12 * T_cloud);
    // The output path's kinetic energy, block by block without M (multibody/outputs.cc).
    EXPECT_NEAR(BodyKineticEnergy(f.body(), p, v), T_cloud, 1e-12 * T_cloud);
    EXPECT_LE((Qv - Qv_cloud).norm(), 1e-12 * Qv_cloud.norm());
  }
}

// Lagrange: d/dt(∂T/∂ṗ) − ∂T/∂p = M p̈ − Q_v  ⇒  Q_v = −Ṁṗ + ∂T/∂p, with Ṁ = Σ ∂M/∂p_i ṗ_i
// and ∂T/∂p_i = ½ṗᵀ ∂M/∂p_i ṗ by central differences (h = 1e-5, error ~1e-10).
TEST(FfrfBody, QuadraticVelocitySatisfiesTheLagrangeIdentity) {
  const Fixture f = Make();
  std::mt19937 gen(3);
  const int nb = 3 + kModes;
  for (int trial = 0; trial < 5; ++trial) {
    const Vec p = RandomVec(nb, gen, 1.0);
    const Vec v = RandomVec(nb, gen, 2.0);
    const double h = 1e-5;
    const Mat Mdot =
        (BodyMassMatrix(f.body(), p + h * v) - BodyMassMatrix(f.body(), p - h * v)) / (2.0 * h);
    Vec dTdp(nb);
    for (int i = 0; i < nb; ++i) {
      Vec pp = p, pm = p;
      pp(i) += h;
      pm(i) -= h;
      dTdp(i) = 0.5 * v.dot((BodyMassMatrix(f.body(), pp) - BodyMassMatrix(f.body(), pm)) * v) /
                (2.0 * h);
    }
    const Vec lagrange = -Mdot * v + dTdp;
    const Vec Qv = BodyQuadraticVelocity(f.body(), p, v);
    EXPECT_LE((Qv - lagrange).norm(), 1e-8 * Qv.norm()) << "trial " << trial;
  }
}

// q = 0: M_RR = m I, M_Rθ = A J S̄₀ (centre of mass S̄₀/m), M_θθ = J₀ = Σ m |ū₀|².
TEST(FfrfBody, UndeformedMassMatrixReproducesMassCentreAndInertia) {
  const Fixture f = Make();
  double m = 0.0, J0 = 0.0;
  Vec2 S0 = Vec2::Zero();
  for (int k = 0; k < kPoints; ++k) {
    m += f.cloud.m[k];
    S0 += f.cloud.m[k] * f.cloud.u0[k];
    J0 += f.cloud.m[k] * f.cloud.u0[k].squaredNorm();
  }
  const double th = 0.7;
  Vec p = Vec::Zero(3 + kModes);
  p(0) = 0.3;
  p(1) = -0.2;
  p(2) = th;
  const Mat M = BodyMassMatrix(f.body(), p);
  EXPECT_NEAR(M(0, 0), m, 1e-14);
  EXPECT_NEAR(M(1, 1), m, 1e-14);
  EXPECT_EQ(M(0, 1), 0.0);
  const Vec2 com_world = Rot(th) * (S0 / m);
  // M_Rθ = A J S̄₀ = m J (A c): (−m c_y, m c_x) in world axes.
  EXPECT_NEAR(M(0, 2), -m * com_world.y(), 1e-14);
  EXPECT_NEAR(M(1, 2), m * com_world.x(), 1e-14);
  EXPECT_NEAR(M(2, 2), J0, 1e-14);
}

// A rigid body is the n = 0 case: S̄₀ = m c, J₀ = I_c + m|c|² (parallel-axis theorem).
TEST(FfrfBody, RigidBodyWithOffsetCentreIsTheZeroModeCase) {
  MechanismBuilder b;
  const double m = 2.0, Ic = 0.03, th = -0.4;
  const Vec2 c(0.1, -0.05);
  b.AddRigidBody({"block", m, Ic, c});
  const Mechanism model = b.Build();
  const Vec p = (Vec(3) << 0.5, 0.1, th).finished();
  const Mat M = BodyMassMatrix(model.bodies()[0], p);
  const Vec2 ac = Rot(th) * c;
  Mat expected(3, 3);
  expected << m, 0.0, -m * ac.y(), 0.0, m, m * ac.x(), -m * ac.y(), m * ac.x(),
      Ic + m * c.squaredNorm();
  EXPECT_LE((M - expected).cwiseAbs().maxCoeff(), 1e-15);
  // Q_v of a rigid body: centripetal force m θ̇² A c on the frame, no torque.
  const Vec v = (Vec(3) << 1.0, 2.0, 5.0).finished();
  const Vec Qv = BodyQuadraticVelocity(model.bodies()[0], p, v);
  EXPECT_NEAR(Qv(0), m * 25.0 * ac.x(), 1e-13);
  EXPECT_NEAR(Qv(1), m * 25.0 * ac.y(), 1e-13);
  EXPECT_NEAR(Qv(2), 0.0, 1e-15);
}

// The residual of a free body is exactly M v̇ − Q_v + K q + D q̇ (same kernels, no extra terms).
TEST(FfrfBody, ResidualOfAFreeBodyIsTheEquationOfMotion) {
  const Fixture f = Make(DampingSpec::Rayleigh(2.0, 1e-4));
  const Mechanism& m = f.model;
  RunData data(m);
  std::mt19937 gen(4);
  Vec y = RandomVec(m.size(), gen, 1.0), yp = RandomVec(m.size(), gen, 1.0);
  const int nb = 3 + kModes;
  const Vec r = CalcResidual(m, &data, 0.0, y, yp);
  const Vec p = y.head(nb), v = y.segment(nb, nb), vd = yp.segment(nb, nb);
  Vec expected = BodyMassMatrix(f.body(), p) * vd - BodyQuadraticVelocity(f.body(), p, v);
  expected.tail(kModes) += f.body().K * p.tail(kModes) + f.body().D * v.tail(kModes);
  EXPECT_LE((r.segment(nb, nb) - expected).norm(), 1e-12 * expected.norm());
  EXPECT_LE((r.head(nb) - (yp.head(nb) - v)).norm(), 1e-15);  // F1 = ṗ − v (no constraints)
}

// D = M_ff Φ diag(2ζω) Φᵀ M_ff with Φ M_ff-normalised ⇒ Φᵀ D Φ = diag(2 ζ_i ω_i).
TEST(FfrfBody, ModalDampingHasThePrescribedRatios) {
  const std::vector<double> zeta{0.01, 0.02, 0.05, 0.1, 0.5};
  const Fixture f = Make(DampingSpec::ModalRatio(zeta));
  const Body& b = f.body();
  Eigen::GeneralizedSelfAdjointEigenSolver<Mat> ges(b.K, b.Mff);
  const Mat& phi = ges.eigenvectors();
  const Mat modal = phi.transpose() * b.D * phi;
  for (int i = 0; i < kModes; ++i) {
    const double omega = std::sqrt(ges.eigenvalues()(i));
    EXPECT_NEAR(modal(i, i), 2.0 * zeta[i] * omega, 1e-9 * omega) << "mode " << i;
    EXPECT_NEAR(b.modal_frequencies_hz(i), omega / (2.0 * std::numbers::pi), 1e-9 * omega);
    for (int j = 0; j < kModes; ++j)
      if (j != i) {
        EXPECT_NEAR(modal(i, j), 0.0, 1e-9 * omega);
      }
  }
}

// The band's ratio with its octave-wide transitions, written as a weighted geometric mean:
// ζ = below^(1−s) · above^s, s = clamp(log2(f / limit) + 1/2, 0, 1) at each limit.
double SmoothBand(double f) {
  auto s = [f](double limit) { return std::clamp(std::log2(f / limit) + 0.5, 0.0, 1.0); };
  const double low = std::pow(kBandLowRatio, 1.0 - s(kBandLowLimitHz)) *
                     std::pow(kBandMidRatio, s(kBandLowLimitHz));
  const double high = std::pow(kBandMidRatio, 1.0 - s(kBandHighLimitHz)) *
                      std::pow(kBandHighRatio, s(kBandHighLimitHz));
  return f < std::sqrt(kBandLowLimitHz * kBandHighLimitHz) ? low : high;
}

// Band damping: ζ = 1 % below 100 Hz, 10 % below 1 kHz, critical above (named defaults), with
// log-linear transitions over an octave about each limit.
TEST(FfrfBody, FrequencyBandDampingAssignsRatiosByBand) {
  const Fixture f = Make(DampingSpec::FrequencyBand());
  const Body& b = f.body();
  ASSERT_EQ(b.modal_damping_ratios.size(), kModes);
  int checked_bands = 0;
  for (int i = 0; i < kModes; ++i) {
    const double fz = b.modal_frequencies_hz(i);
    EXPECT_NEAR(b.modal_damping_ratios(i), SmoothBand(fz), 1e-12) << fz << " Hz";
    checked_bands += 1;
  }
  EXPECT_EQ(checked_bands, kModes);
  EXPECT_EQ(kBandLowRatio, 0.01);
  EXPECT_EQ(kBandMidRatio, 0.10);
  EXPECT_EQ(kBandHighRatio, 1.0);
}

// The band's ratio does not jump: at each limit it is the geometric mean of its neighbours,
// continuous across it, monotone, and the constant levels hold outside the transitions.
TEST(FfrfBody, BandRatioIsContinuousAcrossItsLimits) {
  const DampingSpec band = DampingSpec::FrequencyBand();
  EXPECT_NEAR(band.BandRatio(kBandHighLimitHz), std::sqrt(kBandMidRatio * kBandHighRatio), 1e-12);
  EXPECT_NEAR(band.BandRatio(kBandLowLimitHz), std::sqrt(kBandLowRatio * kBandMidRatio), 1e-12);
  EXPECT_EQ(band.BandRatio(kBandLowLimitHz / std::sqrt(2.0) * 0.999), kBandLowRatio);
  EXPECT_EQ(band.BandRatio(300.0), kBandMidRatio);
  EXPECT_EQ(band.BandRatio(kBandHighLimitHz * std::sqrt(2.0) * 1.001), kBandHighRatio);
  double previous = 0.0;
  for (double f = 10.0; f < 1e4; f *= 1.001) {
    const double z = band.BandRatio(f);
    EXPECT_GE(z, previous) << f;
    EXPECT_NEAR(z, SmoothBand(f), 1e-12 * z) << f;
    // A 0.1 % change of frequency changes the ratio by at most 0.5 % (the steepest transition,
    // 10x over an octave, is f^3.3).
    EXPECT_LT(z / std::max(previous, 1e-300), previous > 0.0 ? 1.005 : INFINITY) << f;
    previous = z;
  }
  DampingSpec bad = band;
  bad.band_high_limit_hz = 1.5 * bad.band_low_limit_hz;  // the transitions would overlap
  EXPECT_THROW(bad.Validate("damping", 8), InputError);
}

// The synthetic rod alone, with a marker at node 3 offset by d.
struct NodeMarkerRod {
  std::shared_ptr<fem::ReducedRod> rod;
  Mechanism model;
  MarkerId marker;
};
NodeMarkerRod MakeNodeMarkerRod(const Vec2& d) {
  NodeMarkerRod r;
  r.rod = MakeSyntheticRod(kModes, kPoints, 42);
  MechanismBuilder b;
  FlexibleBodySpec s;
  s.name = "rod";
  s.rod = r.rod;
  r.marker = b.AddNodeMarker(b.AddFlexibleBody(s), "m", 3, d);
  r.model = b.Build();
  return r;
}

// A node marker is ReducedRod::Marker(node, offset): ū = ū₀,k + d, S_u = S_u,k + J d S_φ,k.
TEST(FfrfBody, NodeMarkerCarriesTheNodeMotion) {
  const Vec2 d(0.01, -0.02);
  const NodeMarkerRod r = MakeNodeMarkerRod(d);
  const auto& rod = r.rod;
  const Marker& m = r.model.marker(r.marker);
  EXPECT_EQ(m.node, 3);
  EXPECT_LE((m.position - (rod->nodes[3].position + d)).norm(), 1e-15);
  const Mat2X expected_Su = rod->nodes[3].S_u + Jmat() * d * rod->nodes[3].S_phi;
  EXPECT_LE((m.S_u - expected_Su).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LE((m.S_phi - rod->nodes[3].S_phi).cwiseAbs().maxCoeff(), 0.0);
}

// SampleView::Marker before any other query refreshes that marker alone (its body's A(θ), then
// the marker), from scratch left at another state: the kinematics of the full update, and of
// r = R + A(ū + S_u q), ṙ = Ṙ + θ̇ J A(ū + S_u q) + A S_u q̇, φ = θ + φ̄ + S_φ q.
TEST(FfrfBody, AMarkerQueriedAloneHasTheKinematicsOfTheFullUpdate) {
  const NodeMarkerRod r = MakeNodeMarkerRod(Vec2(0.01, -0.02));
  const Mechanism& model = r.model;
  const MarkerId mk = r.marker;
  const int n = model.size(), np = model.num_coordinates();
  std::mt19937 gen(7);
  const Vec y = RandomVec(n, gen, 0.3), other = RandomVec(n, gen, 0.3), yp = Vec::Zero(n);
  RunData data(model);
  UpdateKinematics(model, &data, other.data());
  const MarkerKinematics alone = SampleView(model, &data, 0.0, y.data(), yp.data()).Marker(mk);
  UpdateKinematics(model, &data, y.data());
  const MarkerKinematics& full = MarkerState(data, mk);
  EXPECT_EQ(alone.position, full.position);
  EXPECT_EQ(alone.velocity, full.velocity);
  EXPECT_EQ(alone.angle, full.angle);
  EXPECT_EQ(alone.angular_velocity, full.angular_velocity);

  const Marker& m = model.marker(mk);
  const Vec q = y.segment(kFirstMode, kModes), qd = y.segment(np + kFirstMode, kModes);
  const Mat2 A = Rot(y[kTheta]);
  const Vec2 u = m.position + m.S_u * q;
  EXPECT_LE((alone.position - (Vec2(y[kX], y[kY]) + A * u)).norm(), 1e-14);
  EXPECT_LE((alone.velocity -
             (Vec2(y[np + kX], y[np + kY]) + y[np + kTheta] * Jmat() * A * u + A * m.S_u * qd))
                .norm(),
            1e-14);
  EXPECT_NEAR(alone.angle, y[kTheta] + m.angle + m.S_phi.dot(q), 1e-14);
}

}  // namespace
}  // namespace flexrod::multibody
