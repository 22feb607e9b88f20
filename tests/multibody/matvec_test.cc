// tests/multibody/matvec_test.cc — common/matvec.h, the reduced body's matrix-vector product,
// against Eigen's product at every row count of its blocks and remainders.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include "common/matvec.h"

namespace flexrod {
namespace {

TEST(MatVec, EqualsEigensProductForEveryBlockAndRemainder) {
  // Rows 1 … 37 cover blocks of 8, of 4 and single rows in every combination; columns 1 … 9.
  for (int rows = 1; rows <= 37; ++rows) {
    for (int cols = 1; cols <= 9; ++cols) {
      const Mat A = Mat::Random(rows, cols);
      const Vec x = Vec::Random(cols);
      Vec y = Vec::Constant(rows + 1, 7.0);  // one entry past the end: must stay untouched
      MatVec(A, x.data(), y.data());
      const Vec expected = A * x;
      EXPECT_LE((y.head(rows) - expected).cwiseAbs().maxCoeff(), 1e-15 * cols)
          << rows << " x " << cols;
      EXPECT_EQ(y(rows), 7.0) << rows << " x " << cols;
    }
  }
}

}  // namespace
}  // namespace flexrod
