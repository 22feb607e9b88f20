// common/matvec.h — y = A x for the small dense matrices of a reduced body, and for the banded
// ones of a full FE rod basis (ProductMatrix).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <algorithm>
#include <vector>

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

/// A matrix for repeated products y = A x: kept dense (MatVec above), or, when at most a
/// quarter of it is non-zero, by its non-zeros row by row. The full FE rod's stacked mass,
/// coupling and stiffness rows are banded, 3 to 7 % non-zero at 40 elements
/// (tests/mechanisms/body_products_test.cc), and the dense product spent its time on zeros. Either
/// way each y_i is summed over its non-zero columns in column order, the same floating-point sum
/// (the zeros the dense kernel adds change no bit; only the sign of a zero sum may differ), so the
/// choice changes the speed, not the results.
class ProductMatrix {
 public:
  static constexpr double kSparseFill = 0.25;
  ProductMatrix() = default;
  explicit ProductMatrix(Mat dense) : dense_(std::move(dense)) {
    const Eigen::Index m = dense_.rows(), n = dense_.cols();
    Eigen::Index nnz = 0;
    for (Eigen::Index k = 0; k < dense_.size(); ++k) nnz += dense_.data()[k] != 0.0;
    if (m == 0 || n == 0 || static_cast<double>(nnz) > kSparseFill * static_cast<double>(m * n))
      return;
    start_.reserve(m + 1);
    col_.reserve(nnz);
    val_.reserve(nnz);
    for (Eigen::Index i = 0; i < m; ++i) {
      start_.push_back(static_cast<int>(col_.size()));
      for (Eigen::Index j = 0; j < n; ++j) {
        if (dense_(i, j) == 0.0) continue;
        col_.push_back(static_cast<int>(j));
        val_.push_back(dense_(i, j));
      }
    }
    start_.push_back(static_cast<int>(col_.size()));
  }
  const Mat& dense() const { return dense_; }
  Eigen::Index rows() const { return dense_.rows(); }
  Eigen::Index cols() const { return dense_.cols(); }
  bool sparse() const { return !start_.empty(); }
  /// y = A x, or y += A x with kAdd (y must not alias x).
  template <bool kAdd = false>
  void Apply(const double* __restrict x, double* __restrict y) const {
    if (!sparse()) {
      MatVec<kAdd>(dense_, x, y);
      return;
    }
    const Eigen::Index m = dense_.rows();
    for (Eigen::Index i = 0; i < m; ++i) {
      double acc = 0.0;
      for (int k = start_[i]; k < start_[i + 1]; ++k) acc += val_[k] * x[col_[k]];
      if constexpr (kAdd) {
        y[i] += acc;
      } else {
        y[i] = acc;
      }
    }
  }
  /// y_i += a_ij x_j, term by term in column order into y_i itself (dense: column by column).
  void AddTermwise(const double* __restrict x, double* __restrict y) const {
    const Eigen::Index m = dense_.rows(), n = dense_.cols();
    if (!sparse()) {
      for (Eigen::Index j = 0; j < n; ++j) {
        const double* col = dense_.col(j).data();
        for (Eigen::Index i = 0; i < m; ++i) y[i] += col[i] * x[j];
      }
      return;
    }
    for (Eigen::Index i = 0; i < m; ++i) {
      double acc = y[i];
      for (int k = start_[i]; k < start_[i + 1]; ++k) acc += val_[k] * x[col_[k]];
      y[i] = acc;
    }
  }
  /// B += w A[first_row, first_row + B.rows()), entry by entry (dense: every entry).
  void AddScaledRows(Eigen::Index first_row, double w, Mat* B) const {
    if (!sparse()) {
      *B += w * dense_.middleRows(first_row, B->rows());
      return;
    }
    for (Eigen::Index i = 0; i < B->rows(); ++i) {
      for (int k = start_[first_row + i]; k < start_[first_row + i + 1]; ++k)
        (*B)(i, col_[k]) += w * val_[k];
    }
  }

 private:
  Mat dense_;
  std::vector<int> start_, col_;  // row i's non-zeros: [start_[i], start_[i + 1]) (empty: dense)
  std::vector<double> val_;
};

}  // namespace flexrod
