// multibody/ida_dense_solver.cc — dense LU with partial pivoting as a SUNDIALS linear solver.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "multibody/ida_dense_solver.h"

#include <nvector/nvector_serial.h>
#include <sundials/sundials_linearsolver.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "common/error.h"

namespace flexrod::multibody {

namespace {

// The solve's blocks (DenseLuSolve): L's unit lower 4 × 4 diagonal blocks from column 0 on,
// U's upper ones from column n − 1 back, U's remaining first n mod 4 diagonal entries. Each
// is replaced in place by its inverse (the same triangle), so the substitutions multiply
// instead of running a chain of divisions and dependent multiply-adds per column.
void InvertDiagonalBlocks(double* a, int n) {
  const auto col = [a, n](int k) { return a + static_cast<ptrdiff_t>(k) * n; };
  for (int k = 0; k + 4 <= n; k += 4) {  // L⁻¹ of the unit lower block, column by column
    double *c0 = col(k), *c1 = col(k + 1), *c2 = col(k + 2);
    const double l10 = c0[k + 1], l20 = c0[k + 2], l30 = c0[k + 3], l21 = c1[k + 2],
                 l31 = c1[k + 3], l32 = c2[k + 3];
    const double m10 = -l10, m21 = -l21, m32 = -l32;
    const double m20 = -(l20 + l21 * m10), m31 = -(l31 + l32 * m21);
    c0[k + 1] = m10;
    c0[k + 2] = m20;
    c0[k + 3] = -(l30 + l31 * m10 + l32 * m20);
    c1[k + 2] = m21;
    c1[k + 3] = m31;
    c2[k + 3] = m32;
  }
  int k = n - 1;
  for (; k >= 3; k -= 4) {  // U⁻¹ of the upper block [k − 3, k], column by column
    const int b = k - 3;
    double *c0 = col(b), *c1 = col(b + 1), *c2 = col(b + 2), *c3 = col(b + 3);
    const double r0 = 1.0 / c0[b], r1 = 1.0 / c1[b + 1], r2 = 1.0 / c2[b + 2], r3 = 1.0 / c3[b + 3];
    const double u01 = c1[b], u02 = c2[b], u12 = c2[b + 1], u03 = c3[b], u13 = c3[b + 1],
                 u23 = c3[b + 2];
    const double m01 = -r0 * u01 * r1;
    const double m12 = -r1 * u12 * r2;
    const double m02 = -r0 * (u01 * m12 + u02 * r2);
    const double m23 = -r2 * u23 * r3;
    const double m13 = -r1 * (u12 * m23 + u13 * r3);
    const double m03 = -r0 * (u01 * m13 + u02 * m23 + u03 * r3);
    c0[b] = r0;
    c1[b] = m01;
    c1[b + 1] = r1;
    c2[b] = m02;
    c2[b + 1] = m12;
    c2[b + 2] = r2;
    c3[b] = m03;
    c3[b + 1] = m13;
    c3[b + 2] = m23;
    c3[b + 3] = r3;
  }
  for (; k >= 0; --k) col(k)[k] = 1.0 / col(k)[k];
}

}  // namespace

__attribute__((target_clones("avx2", "default"))) int DenseLuFactor(double* a, int n, int* pivot,
                                                                    double* row_scale) {
  const auto col = [a, n](int k) { return a + static_cast<ptrdiff_t>(k) * n; };
  std::fill_n(row_scale, n, 0.0);
  for (int j = 0; j < n; ++j) {
    const double* cj = col(j);
    for (int i = 0; i < n; ++i) row_scale[i] = std::max(row_scale[i], std::abs(cj[i]));
  }
  for (int i = 0; i < n; ++i) {
    if (!(row_scale[i] > 0.0)) return i + 1;
    row_scale[i] = 1.0 / row_scale[i];
  }
  for (int j = 0; j < n; ++j) {
    double* cj = col(j);
    for (int i = 0; i < n; ++i) cj[i] *= row_scale[i];
  }
  for (int k = 0; k < n; ++k) {
    double* ck = col(k);
    int p = k;
    double largest = std::abs(ck[k]);
    for (int i = k + 1; i < n; ++i) {
      const double v = std::abs(ck[i]);
      if (v > largest) {
        largest = v;
        p = i;
      }
    }
    pivot[k] = p;
    if (!(largest > 0.0)) return k + 1;
    if (p != k) {
      for (int j = 0; j < n; ++j) std::swap(col(j)[k], col(j)[p]);
    }
    const double d = ck[k];
    for (int i = k + 1; i < n; ++i) ck[i] /= d;
    for (int j = k + 1; j < n; ++j) {
      double* cj = col(j);
      const double u = cj[k];
      if (u == 0.0) continue;
      for (int i = k + 1; i < n; ++i) cj[i] -= ck[i] * u;
    }
  }
  InvertDiagonalBlocks(a, n);
  return 0;
}

// The two substitutions go four columns at a time: each pass over b then does four
// multiply-adds per element read and written, where one column per pass is dominated by the
// loop's set-up at the mechanism's sizes (n of 20 to 60; 6 100 -> 3 000 instructions per solve
// at n = 41, callgrind). Each block's four unknowns come from its inverted diagonal block
// (InvertDiagonalBlocks): independent multiply-adds instead of a chain of four divisions and
// dependent updates, which set the solve's time (benchmarks/dense_lu.cc: the exudyn-match
// clearance matrix, n = 37, 0.38 -> 0.23 µs a solve for 2.0 -> 2.3 µs a factorisation; the
// main job's, n = 59, 0.66 -> 0.48 µs for 7.1 -> 7.7 µs; an integration step solves about
// 1.6 times and factors about 0.13 times).
__attribute__((target_clones("avx2", "default"))) void DenseLuSolve(const double* __restrict lu,
                                                                    int n, const int* pivot,
                                                                    const double* row_scale,
                                                                    double* __restrict b) {
  const auto col = [lu, n](int k) { return lu + static_cast<ptrdiff_t>(k) * n; };
  for (int i = 0; i < n; ++i) b[i] *= row_scale[i];
  for (int k = 0; k < n; ++k) {
    if (pivot[k] != k) std::swap(b[k], b[pivot[k]]);
  }
  // L y = P b, L unit lower triangular; its diagonal blocks hold their inverses.
  int k = 0;
  for (; k + 4 <= n; k += 4) {
    const double *c0 = col(k), *c1 = col(k + 1), *c2 = col(k + 2), *c3 = col(k + 3);
    const double b0 = b[k], b1 = b[k + 1], b2 = b[k + 2], b3 = b[k + 3];
    const double x0 = b0;
    const double x1 = b1 + c0[k + 1] * b0;
    const double x2 = b2 + (c0[k + 2] * b0 + c1[k + 2] * b1);
    const double x3 = b3 + (c0[k + 3] * b0 + c1[k + 3] * b1) + c2[k + 3] * b2;
    b[k + 1] = x1;
    b[k + 2] = x2;
    b[k + 3] = x3;
    for (int i = k + 4; i < n; ++i) {
      b[i] -= (c0[i] * x0 + c1[i] * x1) + (c2[i] * x2 + c3[i] * x3);
    }
  }
  for (; k < n; ++k) {
    const double* c = col(k);
    for (int i = k + 1; i < n; ++i) b[i] -= c[i] * b[k];
  }
  // U x = y, from the last column on; its diagonal blocks hold their inverses, the first
  // n mod 4 diagonal entries their reciprocals.
  k = n - 1;
  for (; k >= 3; k -= 4) {
    const double *c3 = col(k), *c2 = col(k - 1), *c1 = col(k - 2), *c0 = col(k - 3);
    const double b0 = b[k - 3], b1 = b[k - 2], b2 = b[k - 1], b3 = b[k];
    const double x3 = c3[k] * b3;
    const double x2 = c2[k - 1] * b2 + c3[k - 1] * b3;
    const double x1 = c1[k - 2] * b1 + (c2[k - 2] * b2 + c3[k - 2] * b3);
    const double x0 = (c0[k - 3] * b0 + c1[k - 3] * b1) + (c2[k - 3] * b2 + c3[k - 3] * b3);
    b[k] = x3;
    b[k - 1] = x2;
    b[k - 2] = x1;
    b[k - 3] = x0;
    for (int i = 0; i < k - 3; ++i) {
      b[i] -= (c3[i] * x3 + c2[i] * x2) + (c1[i] * x1 + c0[i] * x0);
    }
  }
  for (; k >= 0; --k) {
    const double* c = col(k);
    b[k] *= c[k];
    for (int i = 0; i < k; ++i) b[i] -= c[i] * b[k];
  }
}

namespace {

struct DenseLuContent {
  std::vector<int> pivot;
  std::vector<double> row_scale;
  sunindextype last_flag{0};
};

DenseLuContent* Content(SUNLinearSolver S) { return static_cast<DenseLuContent*>(S->content); }

SUNLinearSolver_Type GetType(SUNLinearSolver) { return SUNLINEARSOLVER_DIRECT; }
SUNLinearSolver_ID GetId(SUNLinearSolver) { return SUNLINEARSOLVER_CUSTOM; }
int Initialize(SUNLinearSolver S) {
  Content(S)->last_flag = SUNLS_SUCCESS;
  return SUNLS_SUCCESS;
}
int Setup(SUNLinearSolver S, SUNMatrix A) {
  DenseLuContent* c = Content(S);
  const int n = static_cast<int>(c->pivot.size());
  if (SUNMatGetID(A) != SUNMATRIX_DENSE || SM_ROWS_D(A) != n || SM_COLUMNS_D(A) != n) {
    c->last_flag = SUNLS_ILL_INPUT;
    return SUNLS_ILL_INPUT;
  }
  c->last_flag = DenseLuFactor(SM_DATA_D(A), n, c->pivot.data(), c->row_scale.data());
  return c->last_flag > 0 ? SUNLS_LUFACT_FAIL : SUNLS_SUCCESS;
}
int Solve(SUNLinearSolver S, SUNMatrix A, N_Vector x, N_Vector b, realtype /*tol*/) {
  DenseLuContent* c = Content(S);
  const int n = static_cast<int>(c->pivot.size());
  if (x != b) N_VScale(1.0, b, x);
  DenseLuSolve(SM_DATA_D(A), n, c->pivot.data(), c->row_scale.data(), NV_DATA_S(x));
  c->last_flag = SUNLS_SUCCESS;
  return SUNLS_SUCCESS;
}
sunindextype LastFlag(SUNLinearSolver S) { return Content(S)->last_flag; }
int Space(SUNLinearSolver S, long* lrw, long* liw) {
  *lrw = static_cast<long>(Content(S)->row_scale.size());
  *liw = static_cast<long>(Content(S)->pivot.size()) + 1;
  return SUNLS_SUCCESS;
}
int ZeroDense(SUNMatrix A) {
  std::fill_n(SM_DATA_D(A), SM_LDATA_D(A), 0.0);
  return SUNMAT_SUCCESS;
}
int Free(SUNLinearSolver S) {
  if (S == nullptr) return 0;
  delete Content(S);
  S->content = nullptr;
  SUNLinSolFreeEmpty(S);
  return 0;
}

}  // namespace

SUNLinearSolver MakeDenseLuSolver(SUNMatrix A, SUNContext ctx) {
  if (A == nullptr || SUNMatGetID(A) != SUNMATRIX_DENSE || SM_ROWS_D(A) != SM_COLUMNS_D(A)) {
    throw NumericalError("MakeDenseLuSolver: the matrix is not a square SUNDIALS dense matrix");
  }
  const auto n = static_cast<int>(SM_COLUMNS_D(A));
  A->ops->zero = ZeroDense;
  SUNLinearSolver S = SUNLinSolNewEmpty(ctx);
  if (S == nullptr) throw NumericalError("SUNLinSolNewEmpty returned NULL");
  S->content = new DenseLuContent{std::vector<int>(static_cast<size_t>(n), 0),
                                  std::vector<double>(static_cast<size_t>(n), 0.0)};
  S->ops->gettype = GetType;
  S->ops->getid = GetId;
  S->ops->initialize = Initialize;
  S->ops->setup = Setup;
  S->ops->solve = Solve;
  S->ops->lastflag = LastFlag;
  S->ops->space = Space;
  S->ops->free = Free;
  return S;
}

}  // namespace flexrod::multibody
