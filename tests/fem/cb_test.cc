// SPDX-License-Identifier: GPL-3.0-or-later
// Craig–Bampton and the other reductions: properties that pin them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "common/error.h"
#include "fem/eigensolver.h"
#include "fem/reduced_rod.h"
#include "tests/test_util.h"

namespace flexrod::fem {
namespace {

RodSpec SteelRod(int elements = 20) {
  RodSpec rod;
  rod.material = MaterialByName("steel");
  rod.section = {3.175e-3, 19.05e-3, BendingAxis::kWeak};
  rod.length = 0.28;
  rod.num_elements = elements;
  return rod;
}

RodSpec RodWithClamp(int elements = 20) {
  RodSpec rod = SteelRod(elements);
  // A small-end clamp with its centre of mass off the axis (RIG.md §2).
  rod.attachments.push_back({"clamp", elements, 0.12, 4e-5, Vec2(0.01, 0.008)});
  return rod;
}

Vec FullFrequencies(const RodSpec& rod, const std::vector<int>& fixed, int count) {
  const AssembledRod A = AssembleRod(rod);
  const std::vector<int> free = FreeDofs(rod.num_dofs(), fixed);
  return SolveEigenDense(Mat(Restrict(A.K, free)), Mat(Restrict(A.M, free)), count)
      .frequencies_hz();
}

TEST(CraigBampton, WithAllInteriorModesReproducesTheFullModel) {
  const RodSpec rod = RodWithClamp(10);
  ReductionSpec spec = MechanismReduction(rod, ReductionMethod::kCraigBampton, 0);
  spec.num_modes = rod.num_dofs() - 3 - 3;  // every interior mode
  const ReducedRod r = Reduce(rod, spec);
  const Vec full = FullFrequencies(rod, spec.fixed_dofs, r.num_coordinates());
  ASSERT_EQ(r.frequencies_hz.size(), full.size());
  for (int i = 0; i < full.size(); ++i) EXPECT_NEAR(r.frequencies_hz[i] / full[i], 1.0, 1e-9) << i;
}

TEST(CraigBampton, FrequenciesAreUpperBoundsDecreasingMonotonicallyWithModes) {
  const RodSpec rod = RodWithClamp(30);
  const ReductionSpec base = MechanismReduction(rod, ReductionMethod::kCraigBampton, 0);
  const Vec full = FullFrequencies(rod, base.fixed_dofs, 5);
  Vec previous = Vec::Constant(5, 1e300);
  for (int k = 2; k <= 12; k += 2) {
    ReductionSpec spec = base;
    spec.num_modes = k;
    const Vec f = Reduce(rod, spec).frequencies_hz.head(5);
    for (int i = 0; i < 5; ++i) {
      EXPECT_GE(f[i], full[i] * (1.0 - 1e-12))
          << "mode " << i << " k " << k;  // Rayleigh–Ritz bound
      EXPECT_LE(f[i], previous[i] * (1.0 + 1e-12)) << "mode " << i << " k " << k;
    }
    previous = f;
  }
}

TEST(CraigBampton, StaysAccurateOnAFineMesh) {
  // Clamped-free steel rod with a small-end interface, 4 fixed-interface modes: the reduced
  // fundamental frequency is a Rayleigh–Ritz upper bound whose truncation error does not
  // depend on the mesh (1.6e-5 at 1 000 elements). At 10 000 elements K_ii has cond ~1e16:
  // the reduction measured 2.9e-3 (constraint modes in double, K_r by projection) before the
  // extended-precision band solve and the block-structured K_r, 2.8e-4 after. The full model's
  // frequency comes from the same assembly (ARPACK, shift-invert).
  const RodSpec rod = SteelRod(10000);
  ReductionSpec spec = MechanismReduction(rod, ReductionMethod::kCraigBampton, 4);
  spec.fixed_dofs = {0, 1, 2};  // clamped big end
  spec.interface_nodes = {rod.num_elements};
  const ReducedRod r = Reduce(rod, spec);
  const AssembledRod A = AssembleRod(rod);
  const std::vector<int> free = FreeDofs(rod.num_dofs(), spec.fixed_dofs);
  EigenRequest req;
  req.num_modes = 1;
  const double f_full =
      SolveEigenArpack(Restrict(A.K, free), Restrict(A.M, free), req).frequencies_hz()[0];
  const double rel = r.frequencies_hz[0] / f_full - 1.0;
  EXPECT_GT(rel, -1e-6) << rel;  // an upper bound, up to round-off
  EXPECT_LT(rel, 5e-4) << rel;
}

TEST(MeshPrecision, WarnsWhereRoundOffShowsInTheFrequencies) {
  // Thresholds from the measurements in fem/reduced_rod.h: reductions beyond 10 000 elements,
  // the full model beyond 30 000.
  EXPECT_EQ(MeshPrecisionWarning(SteelRod(10000), ReductionMethod::kCraigBampton), "");
  EXPECT_EQ(MeshPrecisionWarning(SteelRod(30000), ReductionMethod::kFull), "");
  const std::string w = MeshPrecisionWarning(SteelRod(10001), ReductionMethod::kCraigBampton);
  EXPECT_NE(w.find("rod.elements = 10001"), std::string::npos) << w;
  EXPECT_NE(MeshPrecisionWarning(SteelRod(30001), ReductionMethod::kFull), "");
  EXPECT_NE(MeshPrecisionWarning(SteelRod(20000), ReductionMethod::kOrthonormalCraigBampton), "");
}

TEST(CraigBampton, WithZeroModesIsGuyanReduction) {
  const RodSpec rod = SteelRod(8);
  const ReductionSpec spec = MechanismReduction(rod, ReductionMethod::kCraigBampton, 0);
  const ReducedRod r = Reduce(rod, spec);
  ASSERT_EQ(r.num_coordinates(), 3);
  // Guyan: condense the interior dofs statically, by dense algebra independent of the code path.
  const AssembledRod A = AssembleRod(rod);
  const Mat K = Mat(A.K), M = Mat(A.M);
  const int n = rod.num_dofs();
  std::vector<int> b = {n - 3, n - 2, n - 1}, in;
  for (int d = 3; d < n - 3; ++d) in.push_back(d);
  Mat T = Mat::Zero(n, 3);
  Mat Kii(in.size(), in.size()), Kib(in.size(), 3);
  for (size_t i = 0; i < in.size(); ++i) {
    for (size_t j = 0; j < in.size(); ++j) Kii(i, j) = K(in[i], in[j]);
    for (int j = 0; j < 3; ++j) Kib(i, j) = K(in[i], b[j]);
  }
  const Mat psi = -Kii.ldlt().solve(Kib);
  for (int j = 0; j < 3; ++j) T(b[j], j) = 1.0;
  for (size_t i = 0; i < in.size(); ++i) T.row(in[i]) = psi.row(i);
  const Mat Kg = T.transpose() * K * T, Mg = T.transpose() * M * T;
  EXPECT_LE((r.K - Kg).norm(), 1e-9 * Kg.norm());
  EXPECT_LE((r.M - Mg).norm(), 1e-9 * Mg.norm());
}

TEST(OrthonormalCraigBampton, HasIdentityMassDiagonalStiffnessAndTheSameFrequencies) {
  const RodSpec rod = RodWithClamp(20);
  const ReducedRod cb = Reduce(rod, MechanismReduction(rod, ReductionMethod::kCraigBampton, 6));
  const ReducedRod on =
      Reduce(rod, MechanismReduction(rod, ReductionMethod::kOrthonormalCraigBampton, 6));
  const int n = on.num_coordinates();
  ASSERT_EQ(n, cb.num_coordinates());
  EXPECT_LE((on.M - Mat::Identity(n, n)).norm(), 1e-9);
  Mat offdiag = on.K;
  offdiag.diagonal().setZero();
  EXPECT_LE(offdiag.norm(), 1e-9 * on.K.norm());
  for (int i = 0; i < n; ++i) EXPECT_NEAR(on.frequencies_hz[i] / cb.frequencies_hz[i], 1.0, 1e-9);
}

TEST(OrthonormalCraigBampton, DropsRigidBodyModesWhenNothingIsFixed) {
  const RodSpec rod = SteelRod(20);
  ReductionSpec spec;
  spec.method = ReductionMethod::kOrthonormalCraigBampton;
  spec.num_modes = 4;
  spec.interface_nodes = {0, rod.num_nodes() - 1};
  const ReducedRod on = Reduce(rod, spec);
  EXPECT_EQ(on.num_coordinates(), 6 + 4 - 3);
  EXPECT_GT(on.frequencies_hz.minCoeff(), 1.0);
  // Its lowest frequency approaches the free–free first bending mode.
  const Vec ff = FullFrequencies(rod, {}, 4);
  EXPECT_NEAR(on.frequencies_hz[0] / ff[3], 1.0, 1e-3);
}

TEST(FreeFreeReduction, KeepsOnlyElasticModes) {
  const RodSpec rod = SteelRod(20);
  const ReducedRod ff = Reduce(rod, MechanismReduction(rod, ReductionMethod::kFreeFree, 5));
  EXPECT_EQ(ff.num_coordinates(), 5);
  const Vec full = FullFrequencies(rod, {}, 8);
  for (int i = 0; i < 5; ++i) EXPECT_NEAR(ff.frequencies_hz[i] / full[3 + i], 1.0, 1e-9);
}

TEST(FullReduction, IsTheFullModel) {
  const RodSpec rod = SteelRod(10);
  const ReducedRod full = Reduce(rod, MechanismReduction(rod, ReductionMethod::kFull, 0));
  EXPECT_EQ(full.num_coordinates(), rod.num_dofs() - 3);
  const Vec f = FullFrequencies(rod, full.reduction.fixed_dofs, 10);
  for (int i = 0; i < 10; ++i) EXPECT_NEAR(full.frequencies_hz[i] / f[i], 1.0, 1e-10);
}

TEST(InertiaShapeIntegrals, MffEqualsReducedConsistentMass) {
  for (BeamTheory t : {BeamTheory::kEulerBernoulli, BeamTheory::kTimoshenko}) {
    RodSpec rod = RodWithClamp(12);
    rod.theory = t;
    const ReducedRod r = Reduce(rod, MechanismReduction(rod, ReductionMethod::kCraigBampton, 5));
    EXPECT_LE((r.inertia.Mff - r.M).norm(), 1e-10 * r.M.norm());
    EXPECT_LE((r.inertia.Stilde + r.inertia.Stilde.transpose()).norm(), 1e-14);
  }
}

TEST(InertiaShapeIntegrals, RigidPartEqualsFEMassContractedWithRigidFields) {
  RodSpec rod = RodWithClamp(16);
  rod.theory = BeamTheory::kTimoshenko;
  const ReducedRod r = Reduce(rod, MechanismReduction(rod, ReductionMethod::kCraigBampton, 3));
  const Mat M = Mat(AssembleRod(rod).M);
  const int n = rod.num_dofs();
  // Rigid fields: translation x, translation y, rotation about node 0 (small): u = -θ·0, v = θ x.
  Mat R = Mat::Zero(n, 3);
  for (int i = 0; i < rod.num_nodes(); ++i) {
    R(3 * i, 0) = 1.0;
    R(3 * i + 1, 1) = 1.0;
    R(3 * i + 1, 2) = rod.node_x(i);
    R(3 * i + 2, 2) = 1.0;
  }
  const Mat MR = R.transpose() * M * R;
  EXPECT_NEAR(r.inertia.mass, MR(0, 0), 1e-12 * MR(0, 0));
  EXPECT_NEAR(r.inertia.mass, MR(1, 1), 1e-12 * MR(0, 0));
  // First moment: ∫ρ x = M_yθ; ∫ρ y = −M_xθ.
  EXPECT_NEAR(r.inertia.S0.x(), MR(1, 2), 1e-12 * std::abs(MR(1, 2)));
  EXPECT_NEAR(r.inertia.S0.y(), -MR(0, 2), 1e-12 * std::abs(MR(1, 2)));
  EXPECT_NEAR(r.inertia.J0, MR(2, 2), 1e-10 * MR(2, 2));
  const double rod_mass = rod.material.density * rod.section.area() * rod.length;
  EXPECT_NEAR(r.inertia.mass, rod_mass + 0.12, 1e-12);
}

TEST(StrainGauge, CantileverTipLoadGivesBeamTheoryStrain) {
  RodSpec rod = SteelRod(10);
  const ReducedRod full = Reduce(rod, MechanismReduction(rod, ReductionMethod::kFull, 0));
  const double P = 3.0;  // tip force [N]
  Vec f = Vec::Zero(rod.num_dofs());
  f[rod.num_dofs() - 2] = P;
  const Vec u =
      SolveStatic(rod, Mat(AssembleRod(rod).K).sparseView(), f, full.reduction.fixed_dofs);
  const Vec q = full.basis.transpose() * u;  // basis is a selection here
  const double EI = rod.material.youngs_modulus * rod.section.inertia_in_plane();
  const double y = rod.section.half_depth_in_plane();
  for (double x : {0.0, 0.0371, 0.14, 0.2799}) {
    const StrainGaugeRows g = full.Gauge("g", x, y);
    const double eps = (g.axial + g.bending).dot(q);
    const double expected = -y * P * (rod.length - x) / EI;  // ε = −y M(x)/EI
    EXPECT_NEAR(eps, expected, 1e-9 * std::abs(-y * P * rod.length / EI)) << "x = " << x;
  }
}

TEST(ReducedRodFile, RoundTripKeepsEverything) {
  const RodSpec rod = RodWithClamp(12);
  const ReducedRod r = Reduce(rod, MechanismReduction(rod, ReductionMethod::kCraigBampton, 4));
  const std::string path = flexrod::test::ScratchPath("rr_test.h5").string();
  WriteReducedRod(r, path);
  const ReducedRod back = ReadReducedRod(path);
  std::remove(path.c_str());
  EXPECT_EQ(back.rod.num_elements, 12);
  EXPECT_EQ(back.rod.attachments.size(), 1u);
  EXPECT_EQ(back.rod.material.name, r.rod.material.name);
  EXPECT_EQ(back.reduction.interface_nodes, r.reduction.interface_nodes);
  EXPECT_EQ((back.K - r.K).norm(), 0.0);
  EXPECT_EQ((back.basis - r.basis).norm(), 0.0);
  EXPECT_EQ((back.inertia.Stilde - r.inertia.Stilde).norm(), 0.0);
  EXPECT_EQ(back.inertia.J0, r.inertia.J0);
  EXPECT_EQ((back.nodes.back().S_u - r.nodes.back().S_u).norm(), 0.0);
}

TEST(ReductionSpec, RejectsMoreModesThanInteriorDofs) {
  const RodSpec rod = SteelRod(4);
  ReductionSpec spec = MechanismReduction(rod, ReductionMethod::kCraigBampton, 100);
  try {
    Reduce(rod, spec);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "reduction.modes");
    EXPECT_NE(std::string(e.what()).find("100"), std::string::npos);
  }
}

}  // namespace
}  // namespace flexrod::fem
