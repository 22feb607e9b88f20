// tests/multibody/matvec_test.cc — common/matvec.h, the reduced body's matrix-vector products
// (y = A x, y += A x, y = Aᵀ x), against Eigen's at every row count of its blocks and remainders;
// ProductMatrix, which keeps a mostly-zero matrix by its non-zeros, against the dense kernel bit
// for bit.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "common/matvec.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <tuple>

namespace flexrod {
namespace {

TEST(MatVec, EqualsEigensProductsForEveryBlockAndRemainder) {
  // Rows 1 … 37 cover blocks of 8, of 4 and single rows in every combination; columns 0 … 9
  // (0: a body with no strain fields).
  for (int rows = 1; rows <= 37; ++rows) {
    for (int cols = 0; cols <= 9; ++cols) {
      const Mat A = Mat::Random(rows, cols);
      const Vec x = Vec::Random(cols);
      Vec y = Vec::Constant(rows + 1, 7.0);  // one entry past the end: must stay untouched
      MatVec(A, x.data(), y.data());
      const Vec expected = A * x;
      EXPECT_LE((y.head(rows) - expected).norm(), 1e-15 * cols) << rows << " x " << cols;
      EXPECT_EQ(y(rows), 7.0) << rows << " x " << cols;
      MatVec<true>(A, x.data(), y.data());  // y += A x
      EXPECT_LE((y.head(rows) - 2.0 * expected).norm(), 2e-15 * cols) << rows << " x " << cols;
      EXPECT_EQ(y(rows), 7.0) << rows << " x " << cols;
      const Vec u = Vec::Random(rows);
      Vec z = Vec::Constant(cols + 1, 7.0);
      MatTVec(A, u.data(), z.data());  // z = Aᵀ u
      EXPECT_LE((z.head(cols) - A.transpose() * u).norm(), 1e-15 * rows) << rows << " x " << cols;
      EXPECT_EQ(z(cols), 7.0) << rows << " x " << cols;
    }
  }
}

/// A banded rows × cols matrix (|i − j| <= half_width), random inside the band.
Mat Banded(int rows, int cols, int half_width) {
  Mat A = Mat::Zero(rows, cols);
  for (int i = 0; i < rows; ++i)
    for (int j = std::max(0, i - half_width); j <= std::min(cols - 1, i + half_width); ++j)
      A(i, j) = Mat::Random(1, 1)(0, 0);
  return A;
}

TEST(ProductMatrix, KeepsAMostlyZeroMatrixByItsNonZerosAndSumsBitForBitAsTheDenseKernel) {
  // The full FE rod's stacked products are banded (a few % non-zero): sparse; a reduced
  // body's are dense.
  for (const auto& [rows, cols, half_width] :
       {std::tuple{122, 120, 5}, std::tuple{362, 120, 8}, std::tuple{37, 9, 1}}) {
    const Mat A = Banded(rows, cols, half_width);
    const ProductMatrix P(A);
    EXPECT_TRUE(P.sparse()) << rows << " x " << cols;
    EXPECT_EQ(P.dense(), A);
    const Vec x = Vec::Random(cols);
    Vec y_sparse = Vec::Constant(rows + 1, 7.0), y_dense = Vec::Constant(rows + 1, 7.0);
    P.Apply(x.data(), y_sparse.data());
    MatVec(A, x.data(), y_dense.data());
    for (int i = 0; i <= rows; ++i) EXPECT_EQ(y_sparse(i), y_dense(i)) << "row " << i;
    P.Apply<true>(x.data(), y_sparse.data());  // y += A x
    MatVec<true>(A, x.data(), y_dense.data());
    for (int i = 0; i <= rows; ++i) EXPECT_EQ(y_sparse(i), y_dense(i)) << "row " << i;
  }
  const Mat dense = Mat::Random(26, 8);
  const ProductMatrix P(dense);
  EXPECT_FALSE(P.sparse());
  const Vec x = Vec::Random(8);
  Vec y(26), expected(26);
  P.Apply(x.data(), y.data());
  MatVec(dense, x.data(), expected.data());
  EXPECT_EQ(y, expected);
  // A quarter non-zero is still sparse, a little more is not.
  Mat quarter = Mat::Zero(8, 8);
  quarter.topRows(2).setOnes();
  EXPECT_TRUE(ProductMatrix(quarter).sparse());
  quarter(2, 0) = 1.0;
  EXPECT_FALSE(ProductMatrix(quarter).sparse());
}

}  // namespace
}  // namespace flexrod
