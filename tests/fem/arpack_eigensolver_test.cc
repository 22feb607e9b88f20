// tests/fem/arpack_eigensolver_test.cc — SolveEigenArpack against the dense oracle
// (SolveEigenDense) on spring–mass chains: lowest-n requests, shifts inside the spectrum
// (UMFPACK path with Sturm check), frequency windows, a singular stiffness, the small-problem
// fallback, determinism, and bad requests as InputError.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "common/error.h"
#include "fem/eigensolver.h"
#include "tests/fem/arpack_chain.h"

namespace flexrod::fem {
namespace {

using testing::Chain;
using testing::FixedFixedChain;
using testing::FreeFreeChain;
using testing::NonUniformMasses;

// Acceptance against the dense oracle (task brief): eigenvalues to 1e-8 relative, eigenvectors
// to |cos| ≥ 1 − 1e-8 in the M inner product. Both solvers are accurate to ~1e-12 on these
// well-separated spectra, so the margin is wide.
constexpr double kLambdaRelTol = 1e-8;
constexpr double kCosTol = 1e-8;
constexpr double kStiffness = 1.0e4;  // [N/m]

EigenResult Oracle(const Chain& c) { return SolveEigenDense(Mat(c.K), Mat(c.M)); }

/// Compares result column j with oracle column first + j (eigenvalue and M-cosine).
void ExpectMatchesOracle(const EigenResult& r, const EigenResult& oracle, const SpMat& M,
                         int first) {
  for (Eigen::Index j = 0; j < r.eigenvalues.size(); ++j) {
    const double ref = oracle.eigenvalues[first + j];
    EXPECT_LE(std::abs(r.eigenvalues[j] - ref), kLambdaRelTol * std::abs(ref))
        << "mode " << j << ": " << r.eigenvalues[j] << " vs oracle " << ref;
    const double cosine =
        std::abs(r.eigenvectors.col(j).dot(M * oracle.eigenvectors.col(first + j)));
    EXPECT_GE(cosine, 1.0 - kCosTol) << "mode " << j;
  }
}

void ExpectMOrthonormal(const EigenResult& r, const SpMat& M) {
  const Mat G = r.eigenvectors.transpose() * (M * r.eigenvectors);
  const Eigen::Index k = G.rows();
  EXPECT_LE((G - Mat::Identity(k, k)).cwiseAbs().maxCoeff(), 1e-12);
}

void ExpectAscending(const EigenResult& r) {
  for (Eigen::Index j = 1; j < r.eigenvalues.size(); ++j)
    EXPECT_LT(r.eigenvalues[j - 1], r.eigenvalues[j]);
}

TEST(ArpackEigensolver, LowestModesOfNonUniformChainMatchDenseOracle) {
  const Chain c = FixedFixedChain(NonUniformMasses(200), kStiffness);
  EigenRequest req;
  req.num_modes = 15;
  const EigenResult r = SolveEigenArpack(c.K, c.M, req);
  ASSERT_EQ(r.eigenvalues.size(), 15);
  ASSERT_EQ(r.eigenvectors.rows(), 200);
  ASSERT_EQ(r.eigenvectors.cols(), 15);
  EXPECT_GT(r.iterations, 0);  // the Lanczos path ran, not the dense fallback
  ExpectAscending(r);
  ExpectMOrthonormal(r, c.M);
  ExpectMatchesOracle(r, Oracle(c), c.M, 0);
}

TEST(ArpackEigensolver, NonDiagonalMassMatchesDenseOracle) {
  // Coupled mass (coupling 0.1 < m_min/(m_min+m_max) = 0.25 keeps M positive definite).
  const Chain c = FixedFixedChain(NonUniformMasses(200), kStiffness, 0.1);
  EigenRequest req;
  req.num_modes = 10;
  const EigenResult r = SolveEigenArpack(c.K, c.M, req);
  ExpectMOrthonormal(r, c.M);
  ExpectMatchesOracle(r, Oracle(c), c.M, 0);
}

TEST(ArpackEigensolver, ShiftInsideTheSpectrumStillGivesTheLowestModes) {
  // σ between λ₉ and λ₁₀: CHOLMOD rejects K − σM and UMFPACK factorises it. The 4 eigenvalues
  // nearest σ are λ₈..λ₁₁, not the lowest 4; the Sturm count (10 below σ) makes the solver grow
  // the run until it holds λ₀..λ₉, and the lowest 4 of those are returned.
  const Chain c = FixedFixedChain(NonUniformMasses(200), kStiffness);
  const EigenResult oracle = Oracle(c);
  EigenRequest req;
  req.num_modes = 4;
  req.shift = 0.5 * (oracle.eigenvalues[9] + oracle.eigenvalues[10]);
  const EigenResult r = SolveEigenArpack(c.K, c.M, req);
  ASSERT_EQ(r.eigenvalues.size(), 4);
  ExpectMOrthonormal(r, c.M);
  ExpectMatchesOracle(r, oracle, c.M, 0);
}

TEST(ArpackEigensolver, ShiftHighInTheSpectrumGrowsTheRunUntilItHoldsEveryModeBelow) {
  // σ between λ₁₉ and λ₂₀, lowest 2 wanted: the 21 eigenvalues nearest σ include only about
  // a dozen of the 20 below σ (the spectrum is denser above), so the first run is short of
  // the Sturm count and the solver doubles nev before it can return λ₀, λ₁.
  const Chain c = FixedFixedChain(NonUniformMasses(200), kStiffness);
  const EigenResult oracle = Oracle(c);
  EigenRequest req;
  req.num_modes = 2;
  req.shift = 0.5 * (oracle.eigenvalues[19] + oracle.eigenvalues[20]);
  const EigenResult r = SolveEigenArpack(c.K, c.M, req);
  ASSERT_EQ(r.eigenvalues.size(), 2);
  ExpectMOrthonormal(r, c.M);
  ExpectMatchesOracle(r, oracle, c.M, 0);
}

TEST(ArpackEigensolver, WindowFindsExactlyTheModesInside) {
  const Chain c = FixedFixedChain(NonUniformMasses(200), kStiffness);
  const EigenResult oracle = Oracle(c);
  const Vec f = oracle.frequencies_hz();
  EigenRequest req;
  req.min_hz = 0.5 * (f[4] + f[5]);  // modes 5 .. 13 inside
  req.max_hz = 0.5 * (f[13] + f[14]);
  const EigenResult r = SolveEigenArpack(c.K, c.M, req);
  ASSERT_EQ(r.eigenvalues.size(), 9);
  EXPECT_GT(r.iterations, 0);
  ExpectAscending(r);
  ExpectMOrthonormal(r, c.M);
  ExpectMatchesOracle(r, oracle, c.M, 5);
}

TEST(ArpackEigensolver, WindowHighInTheSpectrumFindsExactlyTheModesInside) {
  const Chain c = FixedFixedChain(NonUniformMasses(200), kStiffness);
  const EigenResult oracle = Oracle(c);
  const Vec f = oracle.frequencies_hz();
  EigenRequest req;
  req.min_hz = 0.5 * (f[99] + f[100]);  // modes 100 .. 119 inside
  req.max_hz = 0.5 * (f[119] + f[120]);
  const EigenResult r = SolveEigenArpack(c.K, c.M, req);
  ASSERT_EQ(r.eigenvalues.size(), 20);
  ExpectMOrthonormal(r, c.M);
  ExpectMatchesOracle(r, oracle, c.M, 100);
}

TEST(ArpackEigensolver, WindowFromZeroGivesTheLowestModes) {
  const Chain c = FixedFixedChain(NonUniformMasses(200), kStiffness);
  const EigenResult oracle = Oracle(c);
  const Vec f = oracle.frequencies_hz();
  EigenRequest req;
  req.min_hz = 0.0;
  req.max_hz = 0.5 * (f[6] + f[7]);  // modes 0 .. 6
  const EigenResult r = SolveEigenArpack(c.K, c.M, req);
  ASSERT_EQ(r.eigenvalues.size(), 7);
  ExpectMatchesOracle(r, oracle, c.M, 0);
}

TEST(ArpackEigensolver, WindowBetweenTwoAdjacentModesIsEmpty) {
  const Chain c = FixedFixedChain(NonUniformMasses(200), kStiffness);
  const Vec f = Oracle(c).frequencies_hz();
  EigenRequest req;
  req.min_hz = f[10] + 0.25 * (f[11] - f[10]);
  req.max_hz = f[10] + 0.75 * (f[11] - f[10]);
  const EigenResult r = SolveEigenArpack(c.K, c.M, req);
  EXPECT_EQ(r.eigenvalues.size(), 0);
  EXPECT_EQ(r.eigenvectors.rows(), 200);
  EXPECT_EQ(r.eigenvectors.cols(), 0);
}

TEST(ArpackEigensolver, SingularStiffnessWithNegativeShiftFindsTheRigidMode) {
  // Free–free chain: K has the constant vector in its null space (λ₀ = 0); K − σM with σ < 0
  // is positive definite, so CHOLMOD factorises it.
  const int n = 300;
  const double m = 0.8;
  const Chain c = FreeFreeChain(n, m, kStiffness);
  EigenRequest req;
  req.num_modes = 6;
  req.shift = -1.0;
  const EigenResult r = SolveEigenArpack(c.K, c.M, req);
  const EigenResult oracle = Oracle(c);
  ASSERT_EQ(r.eigenvalues.size(), 6);
  // Zero to round-off relative to the first elastic eigenvalue (≈ 1.4 rad²/s²).
  EXPECT_LE(std::abs(r.eigenvalues[0]), 1e-9 * oracle.eigenvalues[1]);
  // Rigid mode: uniform translation, M-normalised: x = 1/sqrt(n m).
  const Vec rigid = Vec::Constant(n, 1.0 / std::sqrt(n * m));
  EXPECT_GE(std::abs(r.eigenvectors.col(0).dot(c.M * rigid)), 1.0 - kCosTol);
  for (int j = 1; j < 6; ++j) {
    EXPECT_LE(std::abs(r.eigenvalues[j] - oracle.eigenvalues[j]),
              kLambdaRelTol * oracle.eigenvalues[j]);
    EXPECT_GE(std::abs(r.eigenvectors.col(j).dot(c.M * oracle.eigenvectors.col(j))), 1.0 - kCosTol);
  }
  ExpectMOrthonormal(r, c.M);
}

TEST(ArpackEigensolver, SingularStiffnessWindowFromZeroIncludesTheRigidMode) {
  const Chain c = FreeFreeChain(300, 0.8, kStiffness);
  const Vec f = Oracle(c).frequencies_hz();
  EigenRequest req;
  req.max_hz = 0.5 * (f[3] + f[4]);  // rigid mode + 3 elastic modes
  const EigenResult r = SolveEigenArpack(c.K, c.M, req);
  ASSERT_EQ(r.eigenvalues.size(), 4);
  EXPECT_NEAR(r.frequencies_hz()[0], 0.0, 1e-6 * f[1]);
}

TEST(ArpackEigensolver, SmallProblemFallsBackToTheDenseSolver) {
  const Chain c = FixedFixedChain(NonUniformMasses(9), kStiffness);
  EigenRequest req;
  req.num_modes = 5;  // n = 9 ≤ 2·5 + 1
  const EigenResult r = SolveEigenArpack(c.K, c.M, req);
  EXPECT_EQ(r.iterations, 0);
  ASSERT_EQ(r.eigenvalues.size(), 5);
  ExpectMatchesOracle(r, Oracle(c), c.M, 0);
}

TEST(ArpackEigensolver, RepeatedSolvesAreBitIdentical) {
  // The start vector is fixed, so a run does not depend on earlier ARPACK calls.
  const Chain c = FixedFixedChain(NonUniformMasses(200), kStiffness);
  EigenRequest req;
  req.num_modes = 7;
  const EigenResult a = SolveEigenArpack(c.K, c.M, req);
  const EigenResult b = SolveEigenArpack(c.K, c.M, req);
  EXPECT_EQ(a.eigenvalues, b.eigenvalues);
  EXPECT_EQ(a.eigenvectors, b.eigenvectors);
}

TEST(ArpackEigensolver, IterationLimitIsANamedArpackError) {
  // One restart with the minimum ncv cannot converge 30 modes of a 400-dof chain to machine
  // precision: dsaupd returns info = 1.
  const Chain c = FixedFixedChain(NonUniformMasses(400), kStiffness);
  EigenRequest req;
  req.num_modes = 30;
  req.num_lanczos_vectors = 32;
  req.max_iterations = 1;
  try {
    SolveEigenArpack(c.K, c.M, req);
    FAIL() << "expected ArpackError";
  } catch (const ArpackError& e) {
    EXPECT_EQ(e.info(), 1);
    EXPECT_NE(std::string(e.what()).find("maximum number of iterations"), std::string::npos)
        << e.what();
  }
}

TEST(ArpackEigensolver, BadRequestsAreInputErrors) {
  const Chain c = FixedFixedChain(NonUniformMasses(50), kStiffness);
  const auto expect_key = [&](const EigenRequest& req, const std::string& key) {
    try {
      SolveEigenArpack(c.K, c.M, req);
      ADD_FAILURE() << "expected InputError for " << key;
    } catch (const InputError& e) {
      EXPECT_EQ(e.key(), key) << e.what();
    }
  };
  EigenRequest req;
  req.num_modes = 50;  // = n
  expect_key(req, "eigen.num_modes");
  req.num_modes = 51;
  expect_key(req, "eigen.num_modes");
  req.num_modes = 0;
  expect_key(req, "eigen.num_modes");
  req.num_modes = -3;
  expect_key(req, "eigen.num_modes");
  req = EigenRequest{};
  req.min_hz = 10.0;
  req.max_hz = 5.0;
  expect_key(req, "eigen.max_hz");
  req.max_hz = 10.0;  // empty window
  expect_key(req, "eigen.max_hz");
  req.min_hz = -1.0;
  req.max_hz = 5.0;
  expect_key(req, "eigen.min_hz");
  req = EigenRequest{};
  req.num_modes = 10;
  req.num_lanczos_vectors = 10;  // must exceed num_modes
  expect_key(req, "eigen.num_lanczos_vectors");
  req = EigenRequest{};
  req.max_iterations = 0;
  expect_key(req, "eigen.max_iterations");
  req = EigenRequest{};
  req.tolerance = -1e-3;
  expect_key(req, "eigen.tolerance");
}

}  // namespace
}  // namespace flexrod::fem
