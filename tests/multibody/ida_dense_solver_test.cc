// tests/multibody/ida_dense_solver_test.cc — the dense LU of multibody/ida_dense_solver.h:
// solutions with a componentwise backward error at round-off (Oettli–Prager: the computed x
// solves (A + δA) x = b + δb with |δA| <= ω|A|, |δb| <= ω|b|), and equal to an independent
// factorisation (Eigen's full-pivoting LU) to the matrix's conditioning; pivoting through zero
// diagonals, badly row-scaled saddle-point matrices like the GGL iteration matrix, singular
// matrices reported by their column, every size around the four-column blocks; and the
// SUNDIALS solver built on it.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "multibody/ida_dense_solver.h"

#include <gtest/gtest.h>
#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "common/eigen.h"
#include "common/error.h"

namespace flexrod::multibody {
namespace {

/// max_i |A x − b|_i / (|A| |x| + |b|)_i (Oettli–Prager componentwise backward error).
double BackwardError(const Mat& A, const Vec& x, const Vec& b) {
  const Vec r = A * x - b;
  const Vec s = A.cwiseAbs() * x.cwiseAbs() + b.cwiseAbs();
  double w = 0.0;
  for (Eigen::Index i = 0; i < r.size(); ++i) w = std::max(w, std::abs(r[i]) / s[i]);
  return w;
}

/// Solves with DenseLuFactor / DenseLuSolve; returns the factor's code in *info.
Vec DenseSolve(const Mat& A, const Vec& b, int* info) {
  const int n = static_cast<int>(A.rows());
  Mat lu = A;  // column-major, leading dimension n
  std::vector<int> pivot(static_cast<size_t>(n));
  std::vector<double> scale(static_cast<size_t>(n));
  *info = DenseLuFactor(lu.data(), n, pivot.data(), scale.data());
  Vec x = b;
  if (*info == 0) DenseLuSolve(lu.data(), n, pivot.data(), scale.data(), x.data());
  return x;
}

/// The GGL iteration matrix's shape: [[c M + K, Gᵀ], [G, 0]] (zero diagonal block, so
/// pivoting is required), rows scaled by 10^k for k in [0, 10] (mass, stiffness and
/// constraint rows of very different units), about a third of the entries non-zero.
Mat SaddlePoint(int nq, int nc, std::mt19937* gen) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), e(0.0, 10.0);
  std::bernoulli_distribution keep(0.3);
  const int n = nq + nc;
  Mat A = Mat::Zero(n, n);
  for (int i = 0; i < nq; ++i) {
    A(i, i) = 4.0 + u(*gen);
    for (int j = 0; j < nq; ++j) {
      if (j != i && keep(*gen)) A(i, j) = u(*gen);
    }
  }
  for (int c = 0; c < nc; ++c) {
    for (int j = 0; j < nq; ++j) {
      if (keep(*gen) || j == c) A(nq + c, j) = A(j, nq + c) = u(*gen);
    }
  }
  for (int i = 0; i < n; ++i) A.row(i) *= std::pow(10.0, e(*gen));
  return A;
}

TEST(DenseLu, SolvesEverySizeToRoundOffAndAgreesWithAFullPivotingLu) {
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int n = 1; n <= 61; ++n) {  // 1..61: every remainder of the four-column blocks
    for (int trial = 0; trial < 3; ++trial) {
      Mat A(n, n);
      for (Eigen::Index k = 0; k < A.size(); ++k) A.data()[k] = u(gen);
      Vec b(n);
      for (Eigen::Index i = 0; i < n; ++i) b[i] = u(gen);
      int info = -1;
      const Vec x = DenseSolve(A, b, &info);
      ASSERT_EQ(info, 0) << n;
      EXPECT_LT(BackwardError(A, x, b), 4e-15 * n) << n;
      const Eigen::FullPivLU<Mat> ref(A);
      const double cond = ref.rcond() > 0.0 ? 1.0 / ref.rcond() : 1e300;
      EXPECT_LT((x - ref.solve(b)).norm(), 1e-14 * n * cond * x.norm()) << n;
    }
  }
}

TEST(DenseLu, SolvesBadlyRowScaledSaddlePointMatricesToRoundOff) {
  // Without the row equilibration, partial pivoting compares entries of rows in different
  // units; on such matrices (and on the exudyn-match clearance Jacobians) its componentwise
  // backward error was 1e-8 instead of round-off.
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const auto& [nq, nc] : {std::pair{12, 4}, std::pair{18, 6}, std::pair{29, 8}}) {
    for (int trial = 0; trial < 10; ++trial) {
      const Mat A = SaddlePoint(nq, nc, &gen);
      Vec b(nq + nc);
      for (Eigen::Index i = 0; i < b.size(); ++i) b[i] = u(gen) * A.row(i).cwiseAbs().maxCoeff();
      int info = -1;
      const Vec x = DenseSolve(A, b, &info);
      ASSERT_EQ(info, 0);
      EXPECT_LT(BackwardError(A, x, b), 1e-14) << nq << " + " << nc << ", trial " << trial;
    }
  }
}

TEST(DenseLu, PivotsThroughAZeroDiagonalExactly) {
  // A permutation matrix: every diagonal entry zero, the solution the permuted right side.
  const int n = 9;
  Mat A = Mat::Zero(n, n);
  for (int i = 0; i < n; ++i) A(i, (i + 4) % n) = 1.0;
  Vec b(n);
  for (int i = 0; i < n; ++i) b[i] = i + 1.0;
  int info = -1;
  const Vec x = DenseSolve(A, b, &info);
  ASSERT_EQ(info, 0);
  for (int i = 0; i < n; ++i) EXPECT_EQ(x[(i + 4) % n], b[i]);
}

TEST(DenseLu, ReportsASingularMatrixByTheColumnWithoutAPivot) {
  Mat A = Mat::Identity(6, 6);
  A.col(3) = A.col(1) + A.col(2);  // column 3 dependent on columns 1 and 2
  Vec b = Vec::Ones(6);
  int info = -1;
  DenseSolve(A, b, &info);
  EXPECT_EQ(info, 4);  // column 3 (1-based 4)
  A = Mat::Identity(6, 6);
  A.row(2).setZero();  // a zero row has no scale: reported by its row
  DenseSolve(A, b, &info);
  EXPECT_EQ(info, 3);
}

TEST(DenseLu, TheSundialsSolverFactorsSolvesAndZeroesItsMatrix) {
  SUNContext ctx = nullptr;
  ASSERT_EQ(SUNContext_Create(nullptr, &ctx), 0);
  const int n = 7;
  SUNMatrix A = SUNDenseMatrix(n, n, ctx);
  SUNLinearSolver S = MakeDenseLuSolver(A, ctx);
  EXPECT_EQ(SUNLinSolGetType(S), SUNLINEARSOLVER_DIRECT);
  std::mt19937 gen(5);
  const Mat M = SaddlePoint(5, 2, &gen);
  std::copy_n(M.data(), n * n, SM_DATA_D(A));
  N_Vector x = N_VNew_Serial(n, ctx), b = N_VNew_Serial(n, ctx);
  for (int i = 0; i < n; ++i) NV_Ith_S(b, i) = std::cos(i + 1.0) * M.row(i).cwiseAbs().maxCoeff();
  ASSERT_EQ(SUNLinSolInitialize(S), SUNLS_SUCCESS);
  ASSERT_EQ(SUNLinSolSetup(S, A), SUNLS_SUCCESS);
  ASSERT_EQ(SUNLinSolSolve(S, A, x, b, 0.0), SUNLS_SUCCESS);
  const Vec xv = Eigen::Map<const Vec>(NV_DATA_S(x), n);
  const Vec bv = Eigen::Map<const Vec>(NV_DATA_S(b), n);
  EXPECT_LT(BackwardError(M, xv, bv), 1e-14);
  // IDA zeroes the matrix before each Jacobian through the matrix's own operation.
  ASSERT_EQ(SUNMatZero(A), SUNMAT_SUCCESS);
  EXPECT_TRUE(std::all_of(SM_DATA_D(A), SM_DATA_D(A) + n * n, [](double v) { return v == 0.0; }));
  // A singular matrix is a recoverable set-up failure (IDA retries with a smaller step).
  EXPECT_EQ(SUNLinSolSetup(S, A), SUNLS_LUFACT_FAIL);
  EXPECT_GT(SUNLinSolLastFlag(S), 0);
  N_VDestroy(x);
  N_VDestroy(b);
  SUNLinSolFree(S);
  SUNMatDestroy(A);
  SUNContext_Free(&ctx);
}

TEST(DenseLu, RefusesAMatrixThatIsNotSquareAndDense) {
  SUNContext ctx = nullptr;
  ASSERT_EQ(SUNContext_Create(nullptr, &ctx), 0);
  SUNMatrix A = SUNDenseMatrix(4, 3, ctx);
  EXPECT_THROW(MakeDenseLuSolver(A, ctx), NumericalError);
  SUNMatDestroy(A);
  SUNContext_Free(&ctx);
}

}  // namespace
}  // namespace flexrod::multibody
