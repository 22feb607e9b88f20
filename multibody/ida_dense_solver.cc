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
  return 0;
}

// The two substitutions go four columns at a time: each pass over b then does four
// multiply-adds per element read and written, where one column per pass is dominated by the
// loop's set-up at the mechanism's sizes (n of 20 to 60; 6 100 -> 3 000 instructions per solve
// at n = 41, callgrind).
__attribute__((target_clones("avx2", "default"))) void DenseLuSolve(const double* __restrict lu,
                                                                    int n, const int* pivot,
                                                                    const double* row_scale,
                                                                    double* __restrict b) {
  const auto col = [lu, n](int k) { return lu + static_cast<ptrdiff_t>(k) * n; };
  for (int i = 0; i < n; ++i) b[i] *= row_scale[i];
  for (int k = 0; k < n; ++k) {
    if (pivot[k] != k) std::swap(b[k], b[pivot[k]]);
  }
  // L y = P b, L unit lower triangular.
  int k = 0;
  for (; k + 4 <= n; k += 4) {
    const double *c0 = col(k), *c1 = col(k + 1), *c2 = col(k + 2), *c3 = col(k + 3);
    const double x0 = b[k];
    const double x1 = b[k + 1] - c0[k + 1] * x0;
    const double x2 = b[k + 2] - (c0[k + 2] * x0 + c1[k + 2] * x1);
    const double x3 = b[k + 3] - (c0[k + 3] * x0 + c1[k + 3] * x1 + c2[k + 3] * x2);
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
  // U x = y, from the last column on.
  k = n - 1;
  for (; k >= 3; k -= 4) {
    const double *c3 = col(k), *c2 = col(k - 1), *c1 = col(k - 2), *c0 = col(k - 3);
    const double x3 = b[k] / c3[k];
    const double x2 = (b[k - 1] - c3[k - 1] * x3) / c2[k - 1];
    const double x1 = (b[k - 2] - (c3[k - 2] * x3 + c2[k - 2] * x2)) / c1[k - 2];
    const double x0 = (b[k - 3] - (c3[k - 3] * x3 + c2[k - 3] * x2 + c1[k - 3] * x1)) / c0[k - 3];
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
    b[k] /= c[k];
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
