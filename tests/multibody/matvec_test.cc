// tests/multibody/matvec_test.cc — common/matvec.h, the reduced body's matrix-vector products
// (y = A x, y += A x, y = Aᵀ x), against Eigen's at every row count of its blocks and remainders.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "common/matvec.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace flexrod
