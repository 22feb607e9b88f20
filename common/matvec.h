// common/matvec.h — y = A x for the small dense matrices of a reduced body.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <algorithm>

#include "common/eigen.h"

namespace flexrod {

/// y = A x, or y += A x with kAdd (A column-major, rows × cols; y must not alias x),
/// for the small dense matrices of a reduced body (tens of rows, its modes as columns). Blocks
/// of 8, then 4 rows are summed over the columns in fixed-size vectors (registers), so y is
/// written once; each y_i is summed in column order, as a plain loop would. Eigen's general
/// matrix-vector kernel spends more on its set-up than on the arithmetic at these sizes, and a
/// coefficient-wise product (lazyProduct) of dynamic size is slower still.
template <bool kAdd = false>
inline void MatVec(const Mat& A, const double* __restrict x, double* __restrict y) {
  const Eigen::Index m = A.rows(), n = A.cols();
  if (n == 0) {  // (a body whose basis carries no elongation field has r = 0 strains)
    if constexpr (!kAdd) std::fill_n(y, m, 0.0);
    return;
  }
  const double* a = A.data();
  Eigen::Index i0 = 0;
  auto rows = [&]<int kRows>() {
    using Block = Eigen::Matrix<double, kRows, 1>;
    for (; i0 + kRows <= m; i0 += kRows) {
      Block acc = Eigen::Map<const Block>(a + i0) * x[0];
      for (Eigen::Index j = 1; j < n; ++j) acc += Eigen::Map<const Block>(a + j * m + i0) * x[j];
      if constexpr (kAdd) {
        Eigen::Map<Block>(y + i0) += acc;
      } else {
        Eigen::Map<Block>(y + i0) = acc;
      }
    }
  };
  rows.template operator()<8>();
  rows.template operator()<4>();
  rows.template operator()<1>();
}

/// y = Aᵀ x (A column-major, rows × cols; y must not alias x): a dot product down each column,
/// for the same small matrices (Eigen's kernel for a transposed product has the same set-up).
inline void MatTVec(const Mat& A, const double* __restrict x, double* __restrict y) {
  const Eigen::Index m = A.rows(), n = A.cols();
  const double* a = A.data();
  for (Eigen::Index j = 0; j < n; ++j) {
    const double* c = a + j * m;
    double acc = 0.0;
    for (Eigen::Index i = 0; i < m; ++i) acc += c[i] * x[i];
    y[j] = acc;
  }
}

}  // namespace flexrod
