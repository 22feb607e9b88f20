// fem/sparse_solver.h — RAII wrappers around SuiteSparse: CHOLMOD (symmetric positive
// definite), UMFPACK (general), KLU (general, circuit-like sparsity). Every library call is
// checked here and nowhere else; a failure throws NumericalError naming the call and status.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <memory>
#include <string>

#include "common/eigen.h"

namespace flexrod::fem {

enum class SparseSolverKind { kCholmod, kUmfpack, kKlu };

/// Factorise once, solve many times. Not copyable; movable.
class SparseSolver {
 public:
  virtual ~SparseSolver() = default;
  /// Factorises A (square, compressed). For CHOLMOD only the lower triangle is read and A must
  /// be symmetric positive definite (NumericalError otherwise).
  virtual void Factorize(const SpMat& A) = 0;
  /// x = A⁻¹ b. Requires a prior Factorize.
  virtual void Solve(const Vec& b, Vec* x) const = 0;
  virtual void Solve(const Mat& B, Mat* X) const = 0;
  virtual const char* name() const = 0;
};

std::unique_ptr<SparseSolver> MakeSparseSolver(SparseSolverKind kind);

}  // namespace flexrod::fem
