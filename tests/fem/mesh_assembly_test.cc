// tests/fem/mesh_assembly_test.cc — RodSpec validation, the assembler, boundary conditions,
// restriction, exact static cantilever solutions, rigid attachments and Euler buckling.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <vector>

#include "fem/rod_mesh.h"
#include "mesh_test_util.h"

namespace flexrod::fem {
namespace {

using testing::DofsOfKind;
using testing::ExpectInputError;
using testing::kPi;
using testing::RigRod;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---------------------------------------------------------------- validation

TEST(RodSpec, RigRodIsValid) { EXPECT_NO_THROW(RigRod(40).Validate()); }

TEST(RodSpec, ValidateNamesEveryOffendingKeyAndValue) {
  const RodSpec good = RigRod(40);
  struct Case {
    void (*mutate)(RodSpec*);
    const char* key;
    const char* value;
  };
  const Case cases[] = {
      {[](RodSpec* r) { r->length = 0.0; }, "rod.length", "0"},
      {[](RodSpec* r) { r->length = -0.28; }, "rod.length", "-0.28"},
      {[](RodSpec* r) { r->length = kNaN; }, "rod.length", "nan"},
      {[](RodSpec* r) { r->num_elements = 0; }, "rod.elements", "0"},
      {[](RodSpec* r) { r->num_elements = -3; }, "rod.elements", "-3"},
      {[](RodSpec* r) { r->section.thickness = -1e-3; }, "rod.thickness", "-0.001"},
      {[](RodSpec* r) { r->section.height = 0.0; }, "rod.height", "0"},
      {[](RodSpec* r) { r->material.youngs_modulus = -1.0; }, "rod.E", "-1"},
      {[](RodSpec* r) { r->material.poisson_ratio = 0.7; }, "rod.nu", "0.7"},
      {[](RodSpec* r) { r->material.density = 0.0; }, "rod.rho", "0"},
      {[](RodSpec* r) {
         r->attachments.push_back({.name = "clamp", .node = 0, .mass = -0.1, .inertia = 0.0});
       },
       "rod.attachments.clamp.mass", "-0.1"},
      {[](RodSpec* r) {
         r->attachments.push_back({.name = "bush", .node = 40, .mass = 0.1, .inertia = -2e-5});
       },
       "rod.attachments.bush.inertia", "-2e-05"},
      {[](RodSpec* r) {
         r->attachments.push_back({.name = "bush", .node = 41, .mass = 0.1, .inertia = 0.0});
       },
       "rod.attachments.bush.node", "41"},
      {[](RodSpec* r) {
         r->attachments.push_back({.name = "", .node = -1, .mass = 0.1, .inertia = 0.0});
       },
       "rod.attachments[0].node", "-1"},
      {[](RodSpec* r) {
         r->attachments.push_back(
             {.name = "bush", .node = 3, .mass = 0.1, .inertia = 0.0, .com_offset = {kNaN, 0.0}});
       },
       "rod.attachments.bush.com_offset", "nan"},
  };
  for (const Case& c : cases) {
    RodSpec rod = good;
    c.mutate(&rod);
    ExpectInputError([&] { rod.Validate(); }, c.key, c.value);
  }
}

TEST(RodSpec, AssemblyValidatesBeforeWorking) {
  RodSpec rod = RigRod(10);
  rod.length = -1.0;
  ExpectInputError([&] { AssembleRod(rod); }, "rod.length", "-1");
}

// ---------------------------------------------------------------- assembly

TEST(Assembly, MatricesAreSymmetricAndSizedByDim) {
  for (MeshDim dim : {MeshDim::kPlanar, MeshDim::kSpatial}) {
    const RodSpec rod = RigRod(12, BeamTheory::kTimoshenko, dim);
    const AssembledRod a = AssembleRod(rod);
    const int n = rod.num_dofs();
    EXPECT_EQ(a.K.rows(), n);
    EXPECT_EQ(a.M.cols(), n);
    EXPECT_LE(Mat(a.K - SpMat(a.K.transpose())).norm(), 1e-14 * Mat(a.K).norm());
    EXPECT_LE(Mat(a.M - SpMat(a.M.transpose())).norm(), 1e-14 * Mat(a.M).norm());
    if (dim == MeshDim::kPlanar) {
      EXPECT_EQ(a.Kg.rows(), n);
    } else {
      EXPECT_EQ(a.Kg.rows(), 0);  // documented: no spatial geometric stiffness
    }
    // Banded: a dof couples only to dofs of its own and neighbouring nodes.
    for (int c = 0; c < a.K.outerSize(); ++c)
      for (SpMat::InnerIterator it(a.K, c); it; ++it)
        EXPECT_LE(std::abs(it.row() / rod.dofs_per_node() - c / rod.dofs_per_node()), 1);
  }
}

TEST(Assembly, FreeRodHasExactlyTheRigidBodyModesAndMassRhoAL) {
  for (MeshDim dim : {MeshDim::kPlanar, MeshDim::kSpatial}) {
    for (BeamTheory t : {BeamTheory::kEulerBernoulli, BeamTheory::kTimoshenko}) {
      for (MassKind kind : {MassKind::kConsistent, MassKind::kLumped}) {
        const RodSpec rod = RigRod(8, t, dim, kind);
        const AssembledRod a = AssembleRod(rod);
        const Mat K(a.K);
        const Vec d = K.diagonal().cwiseSqrt().cwiseInverse();
        const Mat Ks = d.asDiagonal() * K * d.asDiagonal();  // Jacobi scaling keeps inertia
        const Vec eig = Eigen::SelfAdjointEigenSolver<Mat>(Ks).eigenvalues();
        int zeros = 0;
        for (double e : eig) zeros += std::abs(e) < 1e-10 ? 1 : 0;
        EXPECT_EQ(zeros, dim == MeshDim::kPlanar ? 3 : 6);
        EXPECT_GT(eig.minCoeff(), -1e-12);
        const double rho_al = rod.material.density * rod.section.area() * rod.length;
        for (int k = 0; k < (dim == MeshDim::kPlanar ? 2 : 3); ++k) {
          Vec r = Vec::Zero(rod.num_dofs());
          for (int i = 0; i < rod.num_nodes(); ++i) r[i * rod.dofs_per_node() + k] = 1.0;
          EXPECT_NEAR(r.dot(a.M * r), rho_al, 1e-13 * rho_al);
        }
      }
    }
  }
}

// ---------------------------------------------------------------- boundary conditions

TEST(BoundaryConditions, NamedConditionsFixTheDocumentedDofs) {
  const RodSpec p = RigRod(4);  // 5 nodes × 3 dofs, last node dofs 12..14
  EXPECT_EQ(BoundaryDofs(p, "clamped-clamped"), (std::vector<int>{0, 1, 2, 12, 13, 14}));
  EXPECT_EQ(BoundaryDofs(p, "clamped-free"), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(BoundaryDofs(p, "free-free"), (std::vector<int>{}));
  EXPECT_EQ(BoundaryDofs(p, "pinned-pinned"), (std::vector<int>{0, 1, 12, 13}));
  EXPECT_EQ(BoundaryDofs(p, "clamped-pinned"), (std::vector<int>{0, 1, 2, 12, 13}));
  const RodSpec s = RigRod(2, BeamTheory::kEulerBernoulli, MeshDim::kSpatial);  // 3 × 6
  EXPECT_EQ(BoundaryDofs(s, "clamped-free"), (std::vector<int>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(BoundaryDofs(s, "pinned-pinned"), (std::vector<int>{0, 1, 2, 3, 12, 13, 14, 15}));
  EXPECT_EQ(BoundaryDofs(s, "clamped-pinned"),
            (std::vector<int>{0, 1, 2, 3, 4, 5, 12, 13, 14, 15}));
  ExpectInputError([&] { BoundaryDofs(p, "glued-free"); }, "boundary_conditions", "glued-free");
}

TEST(BoundaryConditions, FreeDofsIsTheSortedComplementAndRestrictTakesTheSubmatrix) {
  EXPECT_EQ(FreeDofs(7, {5, 0, 3, 3}), (std::vector<int>{1, 2, 4, 6}));
  const RodSpec rod = RigRod(3, BeamTheory::kTimoshenko);
  const AssembledRod a = AssembleRod(rod);
  const std::vector<int> keep = FreeDofs(rod.num_dofs(), BoundaryDofs(rod, "clamped-pinned"));
  const Mat R(Restrict(a.K, keep));
  const Mat full(a.K);
  ASSERT_EQ(R.rows(), static_cast<Eigen::Index>(keep.size()));
  for (size_t i = 0; i < keep.size(); ++i)
    for (size_t j = 0; j < keep.size(); ++j) EXPECT_EQ(R(i, j), full(keep[i], keep[j]));
}

// ---------------------------------------------------------------- static solutions

TEST(StaticSolve, EulerBernoulliCantileverIsExactForAnyMesh) {
  // Tip load P: v(x) = P x² (3L − x) / (6EI), v(L) = PL³/(3EI), φ(L) = PL²/(2EI) (Gere &
  // Timoshenko, Mechanics of Materials, App. G). Hermite elements are nodally exact.
  for (int ne : {1, 7, 40}) {
    const RodSpec rod = RigRod(ne);
    const AssembledRod a = AssembleRod(rod);
    const double P = 3.0, L = rod.length;
    const double EI = rod.material.youngs_modulus * rod.section.inertia_in_plane();
    Vec f = Vec::Zero(rod.num_dofs());
    f[rod.num_dofs() - 2] = P;
    const Vec u = SolveStatic(rod, a.K, f, BoundaryDofs(rod, "clamped-free"));
    const double tip = P * L * L * L / (3.0 * EI);
    EXPECT_NEAR(u[rod.num_dofs() - 2], tip, 1e-10 * tip) << ne;
    EXPECT_NEAR(u[rod.num_dofs() - 1], P * L * L / (2.0 * EI), 1e-10 * P * L * L / (2.0 * EI));
    for (int i = 0; i < rod.num_nodes(); ++i) {
      const double x = rod.node_x(i);
      EXPECT_NEAR(u[3 * i + 1], P * x * x * (3.0 * L - x) / (6.0 * EI), 1e-10 * tip);
      EXPECT_EQ(u[3 * i], 0.0);  // no axial load
    }
    EXPECT_EQ(u[0], 0.0);  // fixed dofs are returned as zero
  }
}

TEST(StaticSolve, TimoshenkoCantileverAddsExactShearDeflection) {
  // Thick rod (strong axis, L = 60 mm, h = 19 mm): v(L) = PL³/(3EI) + PL/(κGA), φ(L) = PL²/(2EI)
  // (Timoshenko & Gere; the interdependent element is exact for end-loaded cantilevers).
  for (int ne : {1, 5, 40}) {
    RodSpec rod = RigRod(ne, BeamTheory::kTimoshenko);
    rod.section.in_plane = BendingAxis::kStrong;
    rod.length = 0.060;
    const AssembledRod a = AssembleRod(rod);
    const double P = -50.0, L = rod.length;
    const Material& m = rod.material;
    const double EI = m.youngs_modulus * rod.section.inertia_in_plane();
    const double kGA =
        RectSection::CowperShearFactor(m.poisson_ratio) * m.shear_modulus() * rod.section.area();
    Vec f = Vec::Zero(rod.num_dofs());
    f[rod.num_dofs() - 2] = P;
    const Vec u = SolveStatic(rod, a.K, f, BoundaryDofs(rod, "clamped-free"));
    const double bending = P * L * L * L / (3.0 * EI), shear = P * L / kGA;
    EXPECT_GT(std::abs(shear / bending), 0.05);  // shear matters here
    EXPECT_NEAR(u[rod.num_dofs() - 2], bending + shear, 1e-10 * std::abs(bending + shear)) << ne;
    EXPECT_NEAR(u[rod.num_dofs() - 1], P * L * L / (2.0 * EI), 1e-10 * std::abs(P * L * L / EI));
  }
}

TEST(StaticSolve, AxialEndLoadStretchesByPLOverEA) {
  const RodSpec rod = RigRod(9);
  const AssembledRod a = AssembleRod(rod);
  const double N = 1000.0;
  Vec f = Vec::Zero(rod.num_dofs());
  f[rod.num_dofs() - 3] = N;
  const Vec u = SolveStatic(rod, a.K, f, BoundaryDofs(rod, "clamped-free"));
  const double EA = rod.material.youngs_modulus * rod.section.area();
  for (int i = 0; i < rod.num_nodes(); ++i)
    EXPECT_NEAR(u[3 * i], N * rod.node_x(i) / EA, 1e-12 * N * rod.length / EA);
}

TEST(StaticSolve, SpatialCantileverBendsInBothPlanesAndTwistsWithRightHandSigns) {
  // Tip force F_y: v = F L³/(3EI_in), φz = +F L²/(2EI_in). Tip force F_z: w = F L³/(3EI_out),
  // φy = −F L²/(2EI_out) (right-hand rule: a rotation about +y turns +z towards +x).
  // Tip torque T: φx = T L/(GJ).
  for (BeamTheory t : {BeamTheory::kEulerBernoulli, BeamTheory::kTimoshenko}) {
    const RodSpec rod = RigRod(6, t, MeshDim::kSpatial);
    const AssembledRod a = AssembleRod(rod);
    const int tip = 6 * rod.num_elements;
    const double Fy = 2.0, Fz = -7.0, T = 0.3, L = rod.length;
    Vec f = Vec::Zero(rod.num_dofs());
    f[tip + 1] = Fy;
    f[tip + 2] = Fz;
    f[tip + 3] = T;
    const Vec u = SolveStatic(rod, a.K, f, BoundaryDofs(rod, "clamped-free"));
    const Material& m = rod.material;
    const double EIin = m.youngs_modulus * rod.section.inertia_in_plane();
    const double EIout = m.youngs_modulus * rod.section.inertia_out_of_plane();
    const double kGA =
        RectSection::CowperShearFactor(m.poisson_ratio) * m.shear_modulus() * rod.section.area();
    const double shear = t == BeamTheory::kTimoshenko ? L / kGA : 0.0;
    const double v = Fy * (L * L * L / (3.0 * EIin) + shear);
    const double w = Fz * (L * L * L / (3.0 * EIout) + shear);
    EXPECT_NEAR(u[tip + 1], v, 1e-10 * std::abs(v));
    EXPECT_NEAR(u[tip + 5], Fy * L * L / (2.0 * EIin), 1e-10 * std::abs(Fy * L * L / EIin));
    EXPECT_NEAR(u[tip + 2], w, 1e-10 * std::abs(w));
    EXPECT_NEAR(u[tip + 4], -Fz * L * L / (2.0 * EIout), 1e-10 * std::abs(Fz * L * L / EIout));
    const double twist = T * L / (m.shear_modulus() * rod.section.torsion_constant());
    EXPECT_NEAR(u[tip + 3], twist, 1e-10 * twist);
  }
}

TEST(StaticSolve, UnrestrainedRodIsReportedNotSolved) {
  // Free–free K is singular (three rigid-body modes): CHOLMOD's failed factorisation must
  // surface as NumericalError, never as a silently wrong displacement.
  const RodSpec rod = RigRod(10);
  const AssembledRod a = AssembleRod(rod);
  Vec f = Vec::Zero(rod.num_dofs());
  f[rod.num_dofs() - 2] = 1.0;
  EXPECT_THROW(SolveStatic(rod, a.K, f, BoundaryDofs(rod, "free-free")), NumericalError);
}

// ---------------------------------------------------------------- attachments

/// Rigid-body fields over all nodes: translation along axis k, or rotation about axis k
/// through node 0 (displacement e_k × p, rotation e_k).
Vec Translation(const RodSpec& rod, int k) {
  Vec r = Vec::Zero(rod.num_dofs());
  for (int i = 0; i < rod.num_nodes(); ++i) r[i * rod.dofs_per_node() + k] = 1.0;
  return r;
}
Vec Rotation(const RodSpec& rod, int k) {  // planar: only k = 2 (about z)
  Vec r = Vec::Zero(rod.num_dofs());
  const int dpn = rod.dofs_per_node();
  for (int i = 0; i < rod.num_nodes(); ++i) {
    const Eigen::Vector3d p(rod.node_x(i), 0.0, 0.0);
    const Eigen::Vector3d disp = Eigen::Vector3d::Unit(k).cross(p);
    if (dpn == 3) {
      r.segment<3>(3 * i) = Eigen::Vector3d(disp.x(), disp.y(), 1.0);
    } else {
      r.segment<3>(6 * i) = disp;
      r[6 * i + 3 + k] = 1.0;
    }
  }
  return r;
}

std::vector<RigidAttachment> Attachments(int last_node) {
  return {{.name = "big_end_clamp",
           .node = 0,
           .mass = 0.12,
           .inertia = 3e-5,
           .com_offset = {-0.010, 0.004}},
          {.name = "gauge_block", .node = 4, .mass = 0.05, .inertia = 0.0},
          {.name = "small_end_clamp",
           .node = last_node,
           .mass = 0.35,
           .inertia = 8e-5,
           .com_offset = {0.015, -0.020}}};
}

TEST(Attachments, PlanarMassMatrixReproducesRigidBodyMassCentreAndInertia) {
  // Contracting M with rigid-body fields gives the exact rigid-body properties of rod plus
  // attachments (ffrf-planar.md, "Checks"): the Hermite/interdependent interpolation
  // reproduces rigid motion exactly, and the attachment block follows from its kinetic energy.
  for (BeamTheory t : {BeamTheory::kEulerBernoulli, BeamTheory::kTimoshenko}) {
    RodSpec rod = RigRod(10, t);
    rod.attachments = Attachments(rod.num_elements);
    const AssembledRod a = AssembleRod(rod);
    const double rho = rod.material.density, A = rod.section.area(), L = rod.length;
    double mass = rho * A * L, sx = rho * A * L * L / 2.0, sy = 0.0;
    double inertia =
        rho * A * L * L * L / 3.0 +
        (t == BeamTheory::kTimoshenko ? rho * rod.section.inertia_in_plane() * L : 0.0);
    for (const RigidAttachment& at : rod.attachments) {
      const Vec2 p = Vec2(rod.node_x(at.node), 0.0) + at.com_offset;
      mass += at.mass;
      sx += at.mass * p.x();
      sy += at.mass * p.y();
      inertia += at.inertia + at.mass * p.squaredNorm();
    }
    const Vec tx = Translation(rod, 0), ty = Translation(rod, 1), rz = Rotation(rod, 2);
    EXPECT_NEAR(tx.dot(a.M * tx), mass, 1e-13 * mass);
    EXPECT_NEAR(ty.dot(a.M * ty), mass, 1e-13 * mass);
    EXPECT_NEAR(tx.dot(a.M * ty), 0.0, 1e-15 * mass);
    // First moments: the rotation field moves a point p with velocity (−p_y, p_x).
    EXPECT_NEAR(ty.dot(a.M * rz), sx, 1e-13 * std::abs(sx));
    EXPECT_NEAR(tx.dot(a.M * rz), -sy, 1e-13 * std::abs(sx));
    EXPECT_NEAR(rz.dot(a.M * rz), inertia, 1e-13 * inertia);
  }
}

TEST(Attachments, SpatialMassMatrixReproducesRigidBodyInertiaTensor) {
  for (BeamTheory t : {BeamTheory::kEulerBernoulli, BeamTheory::kTimoshenko}) {
    RodSpec rod = RigRod(10, t, MeshDim::kSpatial);
    rod.attachments = Attachments(rod.num_elements);
    const AssembledRod a = AssembleRod(rod);
    const double rho = rod.material.density, A = rod.section.area(), L = rod.length;
    const double I_in = rod.section.inertia_in_plane(), I_out = rod.section.inertia_out_of_plane();
    const bool timo = t == BeamTheory::kTimoshenko;
    // Rod: line mass along x, polar inertia ρ I_p L (both theories), bending rotary inertia
    // ρ I L about y (I_out) and z (I_in) for Timoshenko only.
    double mass = rho * A * L;
    Eigen::Vector3d first(rho * A * L * L / 2.0, 0.0, 0.0);
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
    inertia(0, 0) = rho * (I_in + I_out) * L;
    inertia(1, 1) = rho * A * L * L * L / 3.0 + (timo ? rho * I_out * L : 0.0);
    inertia(2, 2) = rho * A * L * L * L / 3.0 + (timo ? rho * I_in * L : 0.0);
    for (const RigidAttachment& at : rod.attachments) {
      const Eigen::Vector3d p(rod.node_x(at.node) + at.com_offset.x(), at.com_offset.y(), 0.0);
      mass += at.mass;
      first += at.mass * p;
      inertia += at.mass * (p.squaredNorm() * Eigen::Matrix3d::Identity() - p * p.transpose());
      inertia(2, 2) += at.inertia;
    }
    for (int j = 0; j < 3; ++j) {
      for (int k = 0; k < 3; ++k) {
        const Vec Tj = Translation(rod, j), Tk = Translation(rod, k);
        const Vec Rj = Rotation(rod, j), Rk = Rotation(rod, k);
        EXPECT_NEAR(Tj.dot(a.M * Tk), j == k ? mass : 0.0, 1e-13 * mass) << j << k;
        // Σ m e_j · (e_k × p) = (e_k × S)_j with S the first moment.
        const double moment = Eigen::Vector3d::Unit(k).cross(first)[j];
        EXPECT_NEAR(Tj.dot(a.M * Rk), moment, 1e-13 * first.norm()) << j << k;
        EXPECT_NEAR(Rj.dot(a.M * Rk), inertia(j, k), 1e-13 * inertia.norm()) << j << k;
      }
    }
  }
}

// ---------------------------------------------------------------- dense eigensolver

TEST(DenseEigensolver, ReturnsAscendingMOrthonormalEigenpairs) {
  const RodSpec rod = RigRod(10, BeamTheory::kTimoshenko);
  const AssembledRod a = AssembleRod(rod);
  const std::vector<int> free = FreeDofs(rod.num_dofs(), BoundaryDofs(rod, "clamped-free"));
  const Mat K(Restrict(a.K, free)), M(Restrict(a.M, free));
  const EigenResult all = SolveEigenDense(K, M);
  const Eigen::Index n = K.rows();
  ASSERT_EQ(all.eigenvalues.size(), n);
  ASSERT_EQ(all.num_converged, n);
  for (Eigen::Index i = 1; i < n; ++i) EXPECT_LE(all.eigenvalues[i - 1], all.eigenvalues[i]);
  const Mat& X = all.eigenvectors;
  EXPECT_LE((X.transpose() * M * X - Mat::Identity(n, n)).cwiseAbs().maxCoeff(), 1e-10);
  const Mat residual = K * X - M * X * all.eigenvalues.asDiagonal();
  EXPECT_LE(residual.norm(), 1e-9 * (K * X).norm());
  for (Eigen::Index j = 0; j < n; ++j) {  // sign convention: largest entry positive
    Eigen::Index imax = 0;
    X.col(j).cwiseAbs().maxCoeff(&imax);
    EXPECT_GT(X(imax, j), 0.0);
  }
  const EigenResult low = SolveEigenDense(K, M, 4);
  ASSERT_EQ(low.eigenvalues.size(), 4);
  ASSERT_EQ(low.eigenvectors.cols(), 4);
  EXPECT_LE((low.eigenvalues - all.eigenvalues.head(4)).cwiseAbs().maxCoeff(),
            1e-12 * all.eigenvalues[3]);
  const Vec f = low.frequencies_hz();
  for (int i = 0; i < 4; ++i) EXPECT_DOUBLE_EQ(f[i], std::sqrt(low.eigenvalues[i]) / (2 * kPi));
  EigenResult negative;
  negative.eigenvalues = Vec::Constant(1, -4.0);  // round-off below a rigid mode → 0 Hz
  EXPECT_EQ(negative.frequencies_hz()[0], 0.0);
}

TEST(DenseEigensolver, RejectsSingularMassAndBadModeCounts) {
  const Mat K = Mat::Identity(3, 3);
  Mat M = Mat::Identity(3, 3);
  M(2, 2) = 0.0;  // a massless dof
  EXPECT_THROW(SolveEigenDense(K, M), NumericalError);
  ExpectInputError([&] { SolveEigenDense(K, K, 0); }, "num_modes", "0");
  ExpectInputError([&] { SolveEigenDense(K, K, 4); }, "num_modes", "4");
}

// ---------------------------------------------------------------- geometric stiffness

double CriticalLoad(const RodSpec& rod, const std::string& bc) {
  // (K − P K_G) x = 0  ⇔  K_G x = (1/P) K x: the largest 1/P gives the lowest buckling load.
  const AssembledRod a = AssembleRod(rod);
  const std::vector<int> free = FreeDofs(rod.num_dofs(), BoundaryDofs(rod, bc));
  const EigenResult r = SolveEigenDense(Mat(Restrict(a.Kg, free)), Mat(Restrict(a.K, free)));
  return 1.0 / r.eigenvalues.maxCoeff();
}

TEST(GeometricStiffness, GivesEulerBucklingLoads) {
  // Euler: P_cr = π² EI / (K L)² with K = 1 (pinned–pinned), 2 (clamped–free),
  // 0.5 (clamped–clamped); Timoshenko & Gere, Theory of Elastic Stability, §2.
  // Hermite elements with the consistent K_G converge as h⁴: 40 elements give < 1e-6.
  const RodSpec rod = RigRod(40);
  const double EI = rod.material.youngs_modulus * rod.section.inertia_in_plane();
  const double L = rod.length;
  EXPECT_NEAR(CriticalLoad(rod, "pinned-pinned") / (kPi * kPi * EI / (L * L)), 1.0, 1e-6);
  EXPECT_NEAR(CriticalLoad(rod, "clamped-free") / (kPi * kPi * EI / (4.0 * L * L)), 1.0, 1e-6);
  EXPECT_NEAR(CriticalLoad(rod, "clamped-clamped") / (4.0 * kPi * kPi * EI / (L * L)), 1.0, 1e-6);
}

}  // namespace
}  // namespace flexrod::fem
