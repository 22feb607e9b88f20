// tests/fem/elem_beam_test.cc — element kernels: rigid-body null spaces, mass totals, the
// closed-form matrices against quadrature of the shape functions, equilibrium of the
// Timoshenko interpolation, the geometric stiffness, and planar ⊂ spatial consistency.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "fem/beam_element.h"
#include "mesh_test_util.h"

namespace flexrod::fem {
namespace {

constexpr BeamTheory kTheories[] = {BeamTheory::kEulerBernoulli, BeamTheory::kTimoshenko};
constexpr MassKind kKinds[] = {MassKind::kConsistent, MassKind::kLumped};
constexpr BendingAxis kAxes[] = {BendingAxis::kWeak, BendingAxis::kStrong};

std::string Label(BeamTheory t, BendingAxis a) {
  return std::string(t == BeamTheory::kTimoshenko ? "Timoshenko" : "Euler-Bernoulli") + "/" +
         ToString(a);
}

const Material& Steel() {
  static const Material m = MaterialByName("steel");
  return m;
}

RectSection Section(BendingAxis axis) {
  return RectSection{.thickness = 3.175e-3, .height = 19.05e-3, .in_plane = axis};
}

// A short, thick element (L = 20 mm against a 19 mm strong-axis depth) makes the shear
// parameter Φ ≈ 2.5, so every Φ-dependent term matters.
constexpr double kLength = 0.020;

/// Number of eigenvalues below tol after Jacobi scaling D^-1/2 K D^-1/2 (Sylvester: the
/// inertia is unchanged, and the scaling removes the m vs rad unit disparity). Also returns
/// the smallest scaled eigenvalue through *min_eig.
template <int N>
int CountZeroEigenvalues(const Eigen::Matrix<double, N, N>& K, double* min_eig) {
  const Eigen::Matrix<double, N, 1> d = K.diagonal().cwiseSqrt().cwiseInverse();
  const Eigen::Matrix<double, N, N> Ks = d.asDiagonal() * K * d.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> es(Ks);
  *min_eig = es.eigenvalues().minCoeff();
  int zeros = 0;
  for (int i = 0; i < N; ++i) zeros += std::abs(es.eigenvalues()[i]) < 1e-10 ? 1 : 0;
  return zeros;
}

/// Rigid-body displacement fields of the planar element: x, y translation, rotation about
/// node 1 (u = −y θ = 0 on the axis, v = x θ, φ = θ).
std::array<Eigen::Matrix<double, 6, 1>, 3> PlanarRigidModes(double L) {
  Eigen::Matrix<double, 6, 1> tx, ty, rz;
  tx << 1, 0, 0, 1, 0, 0;
  ty << 0, 1, 0, 0, 1, 0;
  rz << 0, 0, 1, 0, L, 1;
  return {tx, ty, rz};
}

/// Spatial rigid fields: translations, and rotations θ e_k about node 1, displacement θ e_k × x.
/// About y: e_y × (x, 0, 0) = (0, 0, −x) so w = −x, φy = 1 — this pins the w/φy sign.
std::array<Eigen::Matrix<double, 12, 1>, 6> SpatialRigidModes(double L) {
  std::array<Eigen::Matrix<double, 12, 1>, 6> r;
  for (auto& v : r) v.setZero();
  for (int k = 0; k < 3; ++k) r[k](k) = r[k](6 + k) = 1.0;  // translations
  r[3](3) = r[3](9) = 1.0;                                  // about x: torsion
  r[4](4) = r[4](10) = 1.0;                                 // about y
  r[4](8) = -L;
  r[5](5) = r[5](11) = 1.0;  // about z
  r[5](7) = L;
  return r;
}

TEST(PlanarElement, StiffnessIsSymmetricPsdWithExactlyThreeRigidBodyModes) {
  for (BeamTheory t : kTheories) {
    for (BendingAxis a : kAxes) {
      const Matrix6d K = PlanarFrameStiffness(Section(a), Steel(), kLength, t);
      EXPECT_LE((K - K.transpose()).norm(), 1e-14 * K.norm()) << Label(t, a);
      double min_eig = 0.0;
      EXPECT_EQ(CountZeroEigenvalues<6>(K, &min_eig), 3) << Label(t, a);
      EXPECT_GT(min_eig, -1e-12) << Label(t, a);
      for (const auto& r : PlanarRigidModes(kLength))
        EXPECT_LE((K * r).norm(), 1e-13 * K.norm() * r.norm()) << Label(t, a);
    }
  }
}

TEST(SpatialElement, StiffnessIsSymmetricPsdWithExactlySixRigidBodyModes) {
  for (BeamTheory t : kTheories) {
    for (BendingAxis a : kAxes) {
      const Matrix12d K = SpatialFrameStiffness(Section(a), Steel(), kLength, t);
      EXPECT_LE((K - K.transpose()).norm(), 1e-14 * K.norm()) << Label(t, a);
      double min_eig = 0.0;
      EXPECT_EQ(CountZeroEigenvalues<12>(K, &min_eig), 6) << Label(t, a);
      EXPECT_GT(min_eig, -1e-12) << Label(t, a);
      for (const auto& r : SpatialRigidModes(kLength))
        EXPECT_LE((K * r).norm(), 1e-13 * K.norm() * r.norm()) << Label(t, a);
    }
  }
}

TEST(PlanarElement, MassIsSymmetricPositiveDefiniteAndSumsToRhoAL) {
  for (BeamTheory t : kTheories) {
    for (MassKind kind : kKinds) {
      const RectSection s = Section(BendingAxis::kWeak);
      const Matrix6d M = PlanarFrameMass(s, Steel(), kLength, t, kind);
      const double rho_al = Steel().density * s.area() * kLength;
      EXPECT_LE((M - M.transpose()).norm(), 1e-15 * M.norm());
      EXPECT_EQ(Eigen::LLT<Matrix6d>(M).info(), Eigen::Success);
      const auto r = PlanarRigidModes(kLength);
      EXPECT_NEAR(r[0].dot(M * r[0]), rho_al, 1e-13 * rho_al);
      EXPECT_NEAR(r[1].dot(M * r[1]), rho_al, 1e-13 * rho_al);
      EXPECT_NEAR(r[0].dot(M * r[1]), 0.0, 1e-15 * rho_al);
      if (kind == MassKind::kLumped) {
        EXPECT_TRUE(M.isDiagonal());
      }
    }
  }
}

TEST(SpatialElement, MassIsSymmetricPositiveDefiniteAndSumsToRhoAL) {
  for (BeamTheory t : kTheories) {
    for (MassKind kind : kKinds) {
      const RectSection s = Section(BendingAxis::kWeak);
      const Matrix12d M = SpatialFrameMass(s, Steel(), kLength, t, kind);
      const double rho_al = Steel().density * s.area() * kLength;
      EXPECT_LE((M - M.transpose()).norm(), 1e-15 * M.norm());
      EXPECT_EQ(Eigen::LLT<Matrix12d>(M).info(), Eigen::Success);
      const auto r = SpatialRigidModes(kLength);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(r[k].dot(M * r[k]), rho_al, 1e-13 * rho_al);
      // Spinning about the axis: polar moment ρ (I_y + I_z) L in both theories.
      const double polar = Steel().density * (s.inertia_in_plane() + s.inertia_out_of_plane());
      EXPECT_NEAR(r[3].dot(M * r[3]), polar * kLength, 1e-13 * polar * kLength);
      if (kind == MassKind::kLumped) {
        EXPECT_TRUE(M.isDiagonal());
      }
    }
  }
}

TEST(PlanarElement, ConsistentMassEqualsRigidRotationInertiaAboutNodeOne) {
  // ∫ρA x² dx = ρAL³/3 exactly (the interpolation reproduces v = x θ), plus the section's
  // rotary inertia ρIL for Timoshenko only.
  for (BeamTheory t : kTheories) {
    for (BendingAxis a : kAxes) {
      const RectSection s = Section(a);
      const Matrix6d M = PlanarFrameMass(s, Steel(), kLength, t, MassKind::kConsistent);
      const auto r = PlanarRigidModes(kLength);
      const double rho = Steel().density;
      const double expected =
          rho * s.area() * std::pow(kLength, 3) / 3.0 +
          (t == BeamTheory::kTimoshenko ? rho * s.inertia_in_plane() * kLength : 0.0);
      EXPECT_NEAR(r[2].dot(M * r[2]), expected, 1e-13 * expected) << Label(t, a);
    }
  }
}

// Four-point Gauss–Legendre on [0, 1]: exact for polynomials of degree ≤ 7 (cubic × cubic).
constexpr double kGaussX[4] = {0.5 - 0.5 * 0.8611363115940526, 0.5 - 0.5 * 0.3399810435848563,
                               0.5 + 0.5 * 0.3399810435848563, 0.5 + 0.5 * 0.8611363115940526};
constexpr double kGaussW[4] = {0.5 * 0.3478548451374538, 0.5 * 0.6521451548625461,
                               0.5 * 0.6521451548625461, 0.5 * 0.3478548451374538};

/// d/dx of the v row of N by the five-point stencil, exact for polynomials of degree ≤ 4.
Eigen::Matrix<double, 1, 6> SlopeRow(const RectSection& s, BeamTheory t, double xi) {
  const double h = 1e-2;
  auto v = [&](double x) -> Eigen::Matrix<double, 1, 6> {
    return PlanarFrameShape(s, Steel(), kLength, t, x).N.row(1);
  };
  return (8.0 * (v(xi + h) - v(xi - h)) - (v(xi + 2 * h) - v(xi - 2 * h))) / (12.0 * h * kLength);
}

TEST(PlanarElement, ClosedFormMatricesEqualQuadratureOfShapeFunctions) {
  // M = ∫ [ρA (N_uᵀN_u + N_vᵀN_v) + ρI N_ψᵀN_ψ] dx (ρI for Timoshenko only) and
  // K = ∫ [EA u'ᵀu' + EI κᵀκ + κGA γᵀγ] dx with γ = v' − ψ: checks the Friedman–Kosmatka
  // closed forms and the shape functions against each other.
  for (BeamTheory t : kTheories) {
    for (BendingAxis a : kAxes) {
      const RectSection s = Section(a);
      const Material& m = Steel();
      const double EI = m.youngs_modulus * s.inertia_in_plane();
      const double kGA =
          RectSection::CowperShearFactor(m.poisson_ratio) * m.shear_modulus() * s.area();
      const bool timo = t == BeamTheory::kTimoshenko;
      Matrix6d Mq = Matrix6d::Zero(), Kq = Matrix6d::Zero();
      for (int g = 0; g < 4; ++g) {
        const PlanarShape sh = PlanarFrameShape(s, m, kLength, t, kGaussX[g]);
        const double w = kGaussW[g] * kLength;
        const auto Nu = sh.N.row(0), Nv = sh.N.row(1), Npsi = sh.N.row(2);
        Mq += w * m.density * s.area() * (Nu.transpose() * Nu + Nv.transpose() * Nv);
        if (timo) Mq += w * m.density * s.inertia_in_plane() * Npsi.transpose() * Npsi;
        const auto Bu = sh.B.row(0), Bk = sh.B.row(1);
        Kq += w * (m.youngs_modulus * s.area() * Bu.transpose() * Bu + EI * Bk.transpose() * Bk);
        const Eigen::Matrix<double, 1, 6> gamma = SlopeRow(s, t, kGaussX[g]) - Npsi;
        if (timo) {
          Kq += w * kGA * gamma.transpose() * gamma;
        } else {
          EXPECT_LE(gamma.norm(), 1e-9) << "Euler-Bernoulli: ψ = v'";
        }
      }
      const Matrix6d M = PlanarFrameMass(s, m, kLength, t, MassKind::kConsistent);
      const Matrix6d K = PlanarFrameStiffness(s, m, kLength, t);
      EXPECT_LE((Mq - M).cwiseAbs().maxCoeff(), 1e-12 * M.cwiseAbs().maxCoeff()) << Label(t, a);
      EXPECT_LE((Kq - K).cwiseAbs().maxCoeff(), 1e-9 * K.cwiseAbs().maxCoeff()) << Label(t, a);
    }
  }
}

TEST(PlanarElement, ShapeFunctionsInterpolateNodalValues) {
  for (BeamTheory t : kTheories) {
    const RectSection s = Section(BendingAxis::kStrong);
    const PlanarShape at0 = PlanarFrameShape(s, Steel(), kLength, t, 0.0);
    const PlanarShape at1 = PlanarFrameShape(s, Steel(), kLength, t, 1.0);
    Eigen::Matrix<double, 3, 6> e0 = Eigen::Matrix<double, 3, 6>::Zero(), e1 = e0;
    e0(0, 0) = e0(1, 1) = e0(2, 2) = 1.0;
    e1(0, 3) = e1(1, 4) = e1(2, 5) = 1.0;
    EXPECT_LE((at0.N - e0).cwiseAbs().maxCoeff(), 1e-15);
    EXPECT_LE((at1.N - e1).cwiseAbs().maxCoeff(), 1e-15);
  }
}

TEST(PlanarElement, TimoshenkoInterpolationSatisfiesStaticEquilibrium) {
  // Interdependent interpolation: shear strain γ = v' − ψ is constant along the element and
  // the moment equation EI ψ'' + κGA γ = 0 holds pointwise (Friedman & Kosmatka 1993, eq. 4).
  const RectSection s = Section(BendingAxis::kStrong);
  const Material& m = Steel();
  const double EI = m.youngs_modulus * s.inertia_in_plane();
  const double kGA = RectSection::CowperShearFactor(m.poisson_ratio) * m.shear_modulus() * s.area();
  const BeamTheory t = BeamTheory::kTimoshenko;
  const auto gamma = [&](double xi) -> Eigen::Matrix<double, 1, 6> {
    return SlopeRow(s, t, xi) - PlanarFrameShape(s, m, kLength, t, xi).N.row(2);
  };
  const Eigen::Matrix<double, 1, 6> gamma0 = gamma(0.0);
  EXPECT_GT(gamma0.norm(), 1e-3);  // thick element: shear is not negligible
  for (double xi : {0.1, 0.37, 0.5, 0.81, 1.0}) {
    EXPECT_LE((gamma(xi) - gamma0).norm(), 1e-9 * gamma0.norm()) << xi;
    const double h = 1e-2;
    const Eigen::Matrix<double, 1, 6> kappa_slope =
        (PlanarFrameShape(s, m, kLength, t, xi + h).B.row(1) -
         PlanarFrameShape(s, m, kLength, t, xi - h).B.row(1)) /
        (2.0 * h * kLength);  // κ is linear: central difference is exact
    EXPECT_LE((EI * kappa_slope + kGA * gamma(xi)).norm(), 1e-8 * kGA * gamma0.norm()) << xi;
  }
}

TEST(PlanarElement, GeometricStiffnessIsTheHermiteSlopeIntegral) {
  // K_G (per newton) = ∫ v'ᵀ v' dx for the Hermite cubics: null on rigid translations and
  // rᵀ K_G r = L for a rigid rotation (v' = 1 along the element).
  const Matrix6d Kg = PlanarFrameGeometricStiffness(kLength);
  EXPECT_LE((Kg - Kg.transpose()).norm(), 1e-15 * Kg.norm());
  const auto r = PlanarRigidModes(kLength);
  EXPECT_LE((Kg * r[0]).norm(), 1e-15 * Kg.norm());
  EXPECT_LE((Kg * r[1]).norm(), 1e-13 * Kg.norm());
  EXPECT_NEAR(r[2].dot(Kg * r[2]), kLength, 1e-14);
  Matrix6d Kq = Matrix6d::Zero();
  const RectSection s = Section(BendingAxis::kWeak);
  for (int g = 0; g < 4; ++g) {
    const auto slope = SlopeRow(s, BeamTheory::kEulerBernoulli, kGaussX[g]);
    Kq += kGaussW[g] * kLength * slope.transpose() * slope;
  }
  EXPECT_LE((Kq - Kg).cwiseAbs().maxCoeff(), 1e-9 * Kg.cwiseAbs().maxCoeff());
}

/// Restriction of a 12×12 matrix to the given six dofs.
Matrix6d Block(const Matrix12d& A, const std::array<int, 6>& idx) {
  Matrix6d out;
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) out(r, c) = A(idx[r], idx[c]);
  return out;
}

TEST(SpatialElement, ContainsThePlanarElementInBothBendingPlanes) {
  // (u, v, φz) is the planar element with I_in; (u, w, −φy) is the planar element of the
  // section turned by 90° (I_out); torsion is GJ/L with polar mass ρ I_p L/6 [2 1; 1 2].
  const std::array<int, 6> in_plane{0, 1, 5, 6, 7, 11};
  const std::array<int, 6> out_of_plane{0, 2, 4, 6, 8, 10};
  const Matrix6d flip = Eigen::Matrix<double, 6, 1>(1, 1, -1, 1, 1, -1).asDiagonal();
  for (BeamTheory t : kTheories) {
    for (BendingAxis a : kAxes) {
      const RectSection s = Section(a);
      RectSection turned = s;
      turned.in_plane = a == BendingAxis::kWeak ? BendingAxis::kStrong : BendingAxis::kWeak;
      const Matrix12d K = SpatialFrameStiffness(s, Steel(), kLength, t);
      const double tol = 1e-14 * K.cwiseAbs().maxCoeff();
      EXPECT_LE(
          (Block(K, in_plane) - PlanarFrameStiffness(s, Steel(), kLength, t)).cwiseAbs().maxCoeff(),
          tol)
          << Label(t, a);
      EXPECT_LE(
          (Block(K, out_of_plane) - flip * PlanarFrameStiffness(turned, Steel(), kLength, t) * flip)
              .cwiseAbs()
              .maxCoeff(),
          tol)
          << Label(t, a);
      const double GJ = Steel().shear_modulus() * s.torsion_constant();
      EXPECT_NEAR(K(3, 3), GJ / kLength, 1e-14 * GJ / kLength);
      EXPECT_NEAR(K(3, 9), -GJ / kLength, 1e-14 * GJ / kLength);
      for (MassKind kind : kKinds) {
        const Matrix12d M = SpatialFrameMass(s, Steel(), kLength, t, kind);
        const double mtol = 1e-14 * M.cwiseAbs().maxCoeff();
        EXPECT_LE((Block(M, in_plane) - PlanarFrameMass(s, Steel(), kLength, t, kind))
                      .cwiseAbs()
                      .maxCoeff(),
                  mtol)
            << Label(t, a);
        EXPECT_LE((Block(M, out_of_plane) -
                   flip * PlanarFrameMass(turned, Steel(), kLength, t, kind) * flip)
                      .cwiseAbs()
                      .maxCoeff(),
                  mtol)
            << Label(t, a);
      }
      const Matrix12d Mc = SpatialFrameMass(s, Steel(), kLength, t, MassKind::kConsistent);
      const double polar =
          Steel().density * (s.inertia_in_plane() + s.inertia_out_of_plane()) * kLength;
      EXPECT_NEAR(Mc(3, 3), polar / 3.0, 1e-14 * polar);
      EXPECT_NEAR(Mc(3, 9), polar / 6.0, 1e-14 * polar);
    }
  }
}

TEST(PlanarElement, TimoshenkoTendsToEulerBernoulliForSlenderElements) {
  // Φ = 12EI/(κGAL²) ~ (depth/L)²: for a 2 m element on the 3.175 mm weak axis, Φ ≈ 8e-6,
  // so both theories agree to O(Φ).
  const RectSection s = Section(BendingAxis::kWeak);
  const double L = 2.0;
  const Matrix6d Ke = PlanarFrameStiffness(s, Steel(), L, BeamTheory::kEulerBernoulli);
  const Matrix6d Kt = PlanarFrameStiffness(s, Steel(), L, BeamTheory::kTimoshenko);
  const Matrix6d Me =
      PlanarFrameMass(s, Steel(), L, BeamTheory::kEulerBernoulli, MassKind::kConsistent);
  const Matrix6d Mt =
      PlanarFrameMass(s, Steel(), L, BeamTheory::kTimoshenko, MassKind::kConsistent);
  // Compare the bending blocks (v, φ): the axial terms are identical and much larger.
  const std::array<int, 4> bend{1, 2, 4, 5};
  double k_diff = 0.0, k_max = 0.0, m_diff = 0.0, m_max = 0.0;
  for (int r : bend) {
    for (int c : bend) {
      k_diff = std::max(k_diff, std::abs(Kt(r, c) - Ke(r, c)));
      k_max = std::max(k_max, std::abs(Ke(r, c)));
      m_diff = std::max(m_diff, std::abs(Mt(r, c) - Me(r, c)));
      m_max = std::max(m_max, std::abs(Me(r, c)));
    }
  }
  EXPECT_LE(k_diff, 1e-4 * k_max);
  EXPECT_GT(k_diff, 1e-7 * k_max);  // the shear flexibility is still there
  EXPECT_LE(m_diff, 1e-4 * m_max);
}

}  // namespace
}  // namespace flexrod::fem
