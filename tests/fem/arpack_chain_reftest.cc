// tests/fem/arpack_chain_reftest.cc — SolveEigenArpack against the closed-form spectra of
// uniform spring–mass chains (reference values, no other code involved).
//
// Fixed–fixed chain, n masses m, n + 1 springs k: λ_j = (2k/m)(1 − cos(jπ/(n+1))), j = 1..n,
// mode shape x_j(i) ∝ sin(i j π/(n+1)), i = 1..n.
// Free–free chain, n masses m, n − 1 springs k: λ_j = (2k/m)(1 − cos(jπ/n)), j = 0..n−1,
// mode shape x_j(i) ∝ cos((i − 1/2) j π/n).
// (Standard results: K/k is the Dirichlet resp. Neumann discrete Laplacian tridiag(−1, 2, −1),
// diagonalised by the DST-I resp. DCT-II vectors.) Evaluated as (4k/m) sin²(θ/2) to avoid
// cancellation in 1 − cos θ.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "fem/eigensolver.h"
#include "tests/fem/arpack_chain.h"
#include "tests/test_util.h"

namespace flexrod::fem {
namespace {

using testing::Chain;
using testing::FixedFixedChain;
using testing::FreeFreeChain;

using flexrod::test::kPi;
constexpr double kK = 2.5e5;  // spring stiffness [N/m]
constexpr double kM = 0.35;   // mass [kg]
// Closed form vs ARPACK: shift-invert Lanczos at machine-precision tolerance reproduces these
// eigenvalues to ~1e-12 relative; 1e-9 leaves room for the condition of the 1000-dof chain.
constexpr double kLambdaRelTol = 1e-9;
constexpr double kCosTol = 1e-9;

double ChainLambda(double theta) { return 4.0 * kK / kM * std::pow(std::sin(0.5 * theta), 2); }

double MCosine(const Vec& x, const Vec& shape, const SpMat& M) {
  return std::abs(x.dot(M * shape)) / std::sqrt(shape.dot(M * shape));  // x is M-normalised
}

TEST(ArpackChainReference, FixedFixedUniformChainMatchesClosedForm) {
  const int n = 1000;
  const Chain c = FixedFixedChain(std::vector<double>(n, kM), kK);
  EigenRequest req;
  req.num_modes = 20;
  const EigenResult r = SolveEigenArpack(c.K, c.M, req);
  ASSERT_EQ(r.eigenvalues.size(), 20);
  for (int j = 1; j <= 20; ++j) {
    const double theta = j * kPi / (n + 1);
    const double exact = ChainLambda(theta);
    EXPECT_LE(std::abs(r.eigenvalues[j - 1] - exact), kLambdaRelTol * exact) << "j = " << j;
    Vec shape(n);
    for (int i = 1; i <= n; ++i) shape[i - 1] = std::sin(i * theta);
    EXPECT_GE(MCosine(r.eigenvectors.col(j - 1), shape, c.M), 1.0 - kCosTol) << "j = " << j;
  }
}

TEST(ArpackChainReference, FreeFreeUniformChainMatchesClosedFormIncludingZero) {
  const int n = 1000;
  const Chain c = FreeFreeChain(n, kM, kK);
  EigenRequest req;
  req.num_modes = 12;
  req.shift = -10.0;  // below the zero eigenvalue: K − σM positive definite
  const EigenResult r = SolveEigenArpack(c.K, c.M, req);
  ASSERT_EQ(r.eigenvalues.size(), 12);
  const double first_elastic = ChainLambda(kPi / n);
  EXPECT_LE(std::abs(r.eigenvalues[0]), 1e-9 * first_elastic);
  for (int j = 1; j < 12; ++j) {
    const double theta = j * kPi / n;
    const double exact = ChainLambda(theta);
    EXPECT_LE(std::abs(r.eigenvalues[j] - exact), kLambdaRelTol * exact) << "j = " << j;
    Vec shape(n);
    for (int i = 1; i <= n; ++i) shape[i - 1] = std::cos((i - 0.5) * theta);
    EXPECT_GE(MCosine(r.eigenvectors.col(j), shape, c.M), 1.0 - kCosTol) << "j = " << j;
  }
}

TEST(ArpackChainReference, WindowOnUniformChainHoldsExactlyTheClosedFormModes) {
  // Window edges half-way (in λ) between closed-form eigenvalues 40|41 and 55|56: modes
  // j = 41 .. 55 inside.
  const int n = 1000;
  const Chain c = FixedFixedChain(std::vector<double>(n, kM), kK);
  const auto hz = [&](double lambda) { return std::sqrt(lambda) / (2.0 * kPi); };
  const auto lam = [&](int j) { return ChainLambda(j * kPi / (n + 1)); };
  EigenRequest req;
  req.min_hz = hz(0.5 * (lam(40) + lam(41)));
  req.max_hz = hz(0.5 * (lam(55) + lam(56)));
  const EigenResult r = SolveEigenArpack(c.K, c.M, req);
  ASSERT_EQ(r.eigenvalues.size(), 15);
  for (int j = 41; j <= 55; ++j)
    EXPECT_LE(std::abs(r.eigenvalues[j - 41] - lam(j)), kLambdaRelTol * lam(j)) << "j = " << j;
}

}  // namespace
}  // namespace flexrod::fem
