// tests/fem/solver_sparse_test.cc — the SuiteSparse wrappers (fem/sparse_solver.h): each solver
// reproduces A x = b to round-off on random well-conditioned systems, CHOLMOD reads only the
// lower triangle and rejects indefinite matrices naming the failing column, and singular
// matrices are NumericalErrors.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "common/error.h"
#include "fem/sparse_solver.h"

namespace flexrod::fem {
namespace {

// Relative residual ‖A x − b‖ / ‖b‖ accepted for the well-conditioned systems below
// (condition numbers ~ 10–100, so round-off gives ~1e-15).
constexpr double kResidualTol = 1e-12;

/// Random sparse n × n matrix with about `per_column` entries in each column, values in [-1, 1].
SpMat RandomSparse(int n, int per_column, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> row(0, n - 1);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::vector<Triplet> t;
  for (int j = 0; j < n; ++j)
    for (int e = 0; e < per_column; ++e) t.emplace_back(row(rng), j, value(rng));
  SpMat A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

/// Symmetric positive definite: RᵀR + I (eigenvalues ≥ 1).
SpMat RandomSpd(int n, unsigned seed) {
  const SpMat R = RandomSparse(n, 3, seed);
  SpMat I(n, n);
  I.setIdentity();
  SpMat A = SpMat(R.transpose()) * R + I;
  A.makeCompressed();
  return A;
}

/// Unsymmetric and strictly diagonally dominant by rows (hence nonsingular).
SpMat RandomUnsymmetric(int n, unsigned seed) {
  SpMat A = RandomSparse(n, 4, seed);
  Vec row_sum = Vec::Zero(n);
  for (int j = 0; j < A.outerSize(); ++j)
    for (SpMat::InnerIterator it(A, j); it; ++it) row_sum[it.row()] += std::abs(it.value());
  for (int i = 0; i < n; ++i) A.coeffRef(i, i) += row_sum[i] + 1.0;
  A.makeCompressed();
  return A;
}

Vec RandomVector(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  Vec v(n);
  for (int i = 0; i < n; ++i) v[i] = value(rng);
  return v;
}

double RelativeResidual(const SpMat& A, const Vec& x, const Vec& b) {
  return (A * x - b).norm() / b.norm();
}

class AllSolvers : public ::testing::TestWithParam<SparseSolverKind> {};
class GeneralSolvers : public ::testing::TestWithParam<SparseSolverKind> {};

TEST_P(AllSolvers, SolvesRandomSpdSystemToRoundOff) {
  const int n = 400;
  const SpMat A = RandomSpd(n, 11);
  const Vec b = RandomVector(n, 12);
  auto solver = MakeSparseSolver(GetParam());
  solver->Factorize(A);
  Vec x;
  solver->Solve(b, &x);
  EXPECT_LE(RelativeResidual(A, x, b), kResidualTol) << solver->name();
}

TEST_P(AllSolvers, MatrixRightHandSideEqualsColumnByColumnSolve) {
  const int n = 150;
  const SpMat A = RandomSpd(n, 21);
  Mat B(n, 3);
  for (int j = 0; j < 3; ++j) B.col(j) = RandomVector(n, 30 + j);
  auto solver = MakeSparseSolver(GetParam());
  solver->Factorize(A);
  Mat X;
  solver->Solve(B, &X);
  ASSERT_EQ(X.rows(), n);
  ASSERT_EQ(X.cols(), 3);
  for (int j = 0; j < 3; ++j) {
    Vec x;
    solver->Solve(Vec(B.col(j)), &x);
    EXPECT_LE((X.col(j) - x).norm(), 1e-14 * x.norm()) << solver->name() << " column " << j;
    EXPECT_LE(RelativeResidual(A, X.col(j), B.col(j)), kResidualTol) << solver->name();
  }
}

TEST_P(AllSolvers, RefactorisationWithNewValuesAndNewPatternIsExact) {
  // Same pattern, new values (the symbolic analysis is reused), then a different pattern.
  const int n = 200;
  SpMat A = RandomSpd(n, 41);
  auto solver = MakeSparseSolver(GetParam());
  solver->Factorize(A);
  SpMat A2 = A;
  for (int i = 0; i < n; ++i)
    A2.coeffRef(i, i) += 3.0 + 0.01 * i;  // same pattern (diagonal present)
  solver->Factorize(A2);
  const Vec b = RandomVector(n, 42);
  Vec x;
  solver->Solve(b, &x);
  EXPECT_LE(RelativeResidual(A2, x, b), kResidualTol) << solver->name();
  const SpMat A3 = RandomSpd(n, 43);
  solver->Factorize(A3);
  solver->Solve(b, &x);
  EXPECT_LE(RelativeResidual(A3, x, b), kResidualTol) << solver->name();
}

TEST_P(AllSolvers, UncompressedInputGivesTheSameSolution) {
  const int n = 120;
  const SpMat A = RandomSpd(n, 51);
  SpMat U(n, n);  // same matrix, built by insert() and left uncompressed
  U.reserve(Eigen::VectorXi::Constant(n, 40));
  for (int j = 0; j < n; ++j)
    for (SpMat::InnerIterator it(A, j); it; ++it) U.insert(it.row(), j) = it.value();
  ASSERT_FALSE(U.isCompressed());
  const Vec b = RandomVector(n, 52);
  auto solver = MakeSparseSolver(GetParam());
  solver->Factorize(RandomSpd(n, 53));  // then U: a new pattern, given uncompressed
  solver->Factorize(U);
  Vec x;
  solver->Solve(b, &x);
  EXPECT_LE(RelativeResidual(A, x, b), kResidualTol) << solver->name();
  solver->Factorize(A);  // same pattern as U, compressed: the analysis is reused
  solver->Solve(b, &x);
  EXPECT_LE(RelativeResidual(A, x, b), kResidualTol) << solver->name();
  solver->Factorize(U);  // and back, uncompressed
  solver->Solve(b, &x);
  EXPECT_LE(RelativeResidual(A, x, b), kResidualTol) << solver->name();
}

TEST_P(AllSolvers, SolveBeforeFactorizeIsAProgrammingError) {
  auto solver = MakeSparseSolver(GetParam());
  Vec x;
  EXPECT_THROW(solver->Solve(Vec::Ones(4), &x), std::logic_error);
}

TEST_P(GeneralSolvers, SolvesRandomUnsymmetricSystemToRoundOff) {
  const int n = 400;
  const SpMat A = RandomUnsymmetric(n, 61);
  ASSERT_GT((SpMat(A.transpose()) - A).norm(), 1.0);  // really unsymmetric
  const Vec b = RandomVector(n, 62);
  auto solver = MakeSparseSolver(GetParam());
  solver->Factorize(A);
  Vec x;
  solver->Solve(b, &x);
  EXPECT_LE(RelativeResidual(A, x, b), kResidualTol) << solver->name();
}

TEST_P(GeneralSolvers, SingularMatrixIsANumericalError) {
  // Column 2 is zero: structurally and numerically singular.
  const int n = 5;
  std::vector<Triplet> t;
  for (int i = 0; i < n; ++i)
    if (i != 2) t.emplace_back(i, i, 1.0 + i);
  t.emplace_back(2, 1, 0.5);
  SpMat A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  auto solver = MakeSparseSolver(GetParam());
  try {
    solver->Factorize(A);
    FAIL() << solver->name() << " accepted a singular matrix";
  } catch (const NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("singular"), std::string::npos) << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(SparseSolver, AllSolvers,
                         ::testing::Values(SparseSolverKind::kCholmod, SparseSolverKind::kUmfpack,
                                           SparseSolverKind::kKlu));
INSTANTIATE_TEST_SUITE_P(SparseSolver, GeneralSolvers,
                         ::testing::Values(SparseSolverKind::kUmfpack, SparseSolverKind::kKlu));

TEST(CholmodSolver, ReadsOnlyTheLowerTriangle) {
  const int n = 200;
  const SpMat A = RandomSpd(n, 71);
  // Same lower triangle, nonsense strictly upper triangle.
  SpMat garbage = A;
  for (int j = 0; j < garbage.outerSize(); ++j)
    for (SpMat::InnerIterator it(garbage, j); it; ++it)
      if (it.row() < j) it.valueRef() = 1e3 * (1 + it.row());
  const Vec b = RandomVector(n, 72);
  auto solver = MakeSparseSolver(SparseSolverKind::kCholmod);
  solver->Factorize(garbage);
  Vec x;
  solver->Solve(b, &x);
  EXPECT_LE(RelativeResidual(A, x, b), kResidualTol);
}

TEST(CholmodSolver, IndefiniteMatrixNamesTheFailingColumn) {
  // Diagonal, negative in column 2 only: whatever the ordering, the factorisation fails there.
  SpMat A(4, 4);
  A.insert(0, 0) = 4.0;
  A.insert(1, 1) = 3.0;
  A.insert(2, 2) = -2.0;
  A.insert(3, 3) = 5.0;
  A.makeCompressed();
  auto solver = MakeSparseSolver(SparseSolverKind::kCholmod);
  try {
    solver->Factorize(A);
    FAIL() << "CHOLMOD accepted an indefinite matrix";
  } catch (const NumericalError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("not positive definite"), std::string::npos) << what;
    EXPECT_NE(what.find("column 2 "), std::string::npos) << what;
  }
  // The solver stays usable after the failure.
  SpMat spd = A;
  spd.coeffRef(2, 2) = 2.0;
  solver->Factorize(spd);
  Vec x;
  solver->Solve(Vec::Ones(4), &x);
  EXPECT_NEAR(x[2], 0.5, 1e-15);
}

TEST(CholmodSolver, ShiftedLaplacianAboveItsLowestEigenvalueIsRejected) {
  // 1-D Laplacian tridiag(-1, 2, -1) has eigenvalues 2 − 2cos(jπ/(n+1)) ∈ (0, 4); shifting by
  // 1 makes it indefinite (about a quarter of the spectrum goes negative).
  const int n = 100;
  std::vector<Triplet> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 2.0 - 1.0);
    if (i + 1 < n) {
      t.emplace_back(i + 1, i, -1.0);
      t.emplace_back(i, i + 1, -1.0);
    }
  }
  SpMat A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  auto solver = MakeSparseSolver(SparseSolverKind::kCholmod);
  EXPECT_THROW(solver->Factorize(A), NumericalError);
  // UMFPACK and KLU factorise the same indefinite (nonsingular) matrix.
  for (SparseSolverKind kind : {SparseSolverKind::kUmfpack, SparseSolverKind::kKlu}) {
    auto lu = MakeSparseSolver(kind);
    lu->Factorize(A);
    const Vec b = RandomVector(n, 81);
    Vec x;
    lu->Solve(b, &x);
    EXPECT_LE(RelativeResidual(A, x, b), 1e-11) << lu->name();
  }
}

}  // namespace
}  // namespace flexrod::fem
