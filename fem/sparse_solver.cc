// fem/sparse_solver.cc — CHOLMOD, UMFPACK and KLU behind fem::SparseSolver. Every SuiteSparse
// call of flexrod is made in this file and checked here; a failure throws NumericalError naming
// the call, the library status and, where the library reports it, the failing column.
//
// Eigen's SpMat (column-major, int indices, sorted row indices) is already compressed sparse
// column storage, so a compressed SpMat is handed to the libraries without copying its arrays;
// an uncompressed one is compressed into a private copy first. UMFPACK keeps its own compressed
// copy of A because its iterative refinement (umfpack_di_solve) reads A again after Factorize,
// and the interface does not require the caller to keep A alive. A new matrix with the same
// sparsity pattern as the previous one reuses the symbolic analysis (ordering).
//
// Thread safety: one solver object must not be used by two threads at once (the libraries'
// Common objects and CHOLMOD's solve workspace are mutated by Solve). Separate objects are
// independent.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "fem/sparse_solver.h"

#include <cholmod.h>
#include <klu.h>
#include <umfpack.h>

#include <algorithm>
#include <array>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "common/error.h"

namespace flexrod::fem {
namespace {

// ---- shared helpers ---------------------------------------------------------------------------

/// The last message CHOLMOD passed to its error handler on this thread (CHOLMOD's handler has
/// no user-data pointer, so the message cannot be stored in the solver object itself).
thread_local std::string t_cholmod_message;

void RecordCholmodMessage(int /*status*/, const char* /*file*/, int /*line*/, const char* message) {
  t_cholmod_message = message != nullptr ? message : "";
}

/// A compressed view of A: A itself when it is compressed, else a compressed copy in *storage.
const SpMat& Compressed(const SpMat& A, SpMat* storage) {
  if (A.isCompressed()) return A;
  *storage = A;
  storage->makeCompressed();
  return *storage;
}

void CheckSquare(const SpMat& A, const std::string& solver) {
  if (A.rows() != A.cols() || A.rows() == 0) {
    throw NumericalError(solver + ": the matrix must be square and non-empty, got " +
                         std::to_string(A.rows()) + " x " + std::to_string(A.cols()));
  }
}

void CheckSolveSize(Eigen::Index rows, Eigen::Index n, bool factored, const std::string& solver) {
  if (!factored) {
    throw std::logic_error(solver + ": Solve called without a successful Factorize");
  }
  if (rows != n) {
    throw std::logic_error(solver + ": right-hand side has " + std::to_string(rows) +
                           " rows, the factorised matrix " + std::to_string(n));
  }
}

/// Sparsity pattern of the last factorised matrix: a matrix with the same pattern may reuse the
/// symbolic analysis.
class Pattern {
 public:
  void Assign(const SpMat& A) {  // A compressed
    outer_.assign(A.outerIndexPtr(), A.outerIndexPtr() + A.outerSize() + 1);
    inner_.assign(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros());
    rows_ = A.rows();
  }
  void Clear() {
    outer_.clear();
    inner_.clear();
    rows_ = -1;
  }
  bool Matches(const SpMat& A) const {  // A compressed
    if (A.rows() != rows_ || static_cast<size_t>(A.outerSize()) + 1 != outer_.size() ||
        static_cast<size_t>(A.nonZeros()) != inner_.size()) {
      return false;
    }
    return std::equal(outer_.begin(), outer_.end(), A.outerIndexPtr()) &&
           std::equal(inner_.begin(), inner_.end(), A.innerIndexPtr());
  }

 private:
  std::vector<int> outer_, inner_;
  Eigen::Index rows_{-1};
};

// ---- CHOLMOD ----------------------------------------------------------------------------------

const char* CholmodStatusMeaning(int status) {
  switch (status) {
    case CHOLMOD_OK:
      return "success";
    case CHOLMOD_NOT_INSTALLED:
      return "method not installed";
    case CHOLMOD_OUT_OF_MEMORY:
      return "out of memory";
    case CHOLMOD_TOO_LARGE:
      return "integer overflow (problem too large)";
    case CHOLMOD_INVALID:
      return "invalid input";
    case CHOLMOD_GPU_PROBLEM:
      return "GPU error";
    case CHOLMOD_NOT_POSDEF:
      return "matrix not positive definite";
    case CHOLMOD_DSMALL:
      return "diagonal of the factor is tiny";
    default:
      return "unknown status";
  }
}

[[noreturn]] void ThrowCholmod(const char* call, int status) {
  std::string what = std::string("CHOLMOD ") + call + " failed: status " + std::to_string(status) +
                     " (" + CholmodStatusMeaning(status) + ")";
  if (!t_cholmod_message.empty()) what += ": " + t_cholmod_message;
  throw NumericalError(what);
}

/// cholmod_common and the objects allocated through it. Heap-allocated and never moved, so
/// the solver that owns it is movable without touching CHOLMOD's internals.
struct CholmodState {
  cholmod_common common{};
  cholmod_factor* factor{nullptr};
  cholmod_dense* x{nullptr};  // cholmod_solve2 workspace and result, reused between solves
  cholmod_dense* y{nullptr};
  cholmod_dense* e{nullptr};

  CholmodState() {
    if (!cholmod_start(&common)) throw NumericalError("CHOLMOD cholmod_start failed");
    common.print = 0;  // errors are reported by exceptions, not printed
    // Force an LLᵀ factorisation: CHOLMOD's default simplicial LDLᵀ accepts indefinite
    // matrices (it fails only on an exactly zero pivot), and this wrapper promises to reject
    // them. Supernodal factors are LLᵀ anyway.
    common.final_asis = 0;
    common.final_ll = 1;
    common.error_handler = &RecordCholmodMessage;
  }
  ~CholmodState() {
    FreeFactor();
    cholmod_free_dense(&x, &common);
    cholmod_free_dense(&y, &common);
    cholmod_free_dense(&e, &common);
    cholmod_finish(&common);
  }
  CholmodState(const CholmodState&) = delete;
  CholmodState& operator=(const CholmodState&) = delete;
  void FreeFactor() {
    if (factor != nullptr) cholmod_free_factor(&factor, &common);
  }
};

/// cholmod_sparse header over A's arrays (no copy): symmetric, lower triangle read (stype -1).
cholmod_sparse LowerSymmetricView(const SpMat& A) {  // A compressed
  cholmod_sparse v{};
  v.nrow = static_cast<size_t>(A.rows());
  v.ncol = static_cast<size_t>(A.cols());
  v.nzmax = static_cast<size_t>(A.nonZeros());
  // CHOLMOD takes non-const pointers but only reads its input matrix.
  v.p = const_cast<int*>(A.outerIndexPtr());
  v.i = const_cast<int*>(A.innerIndexPtr());
  v.nz = nullptr;
  v.x = const_cast<double*>(A.valuePtr());
  v.z = nullptr;
  v.stype = -1;
  v.itype = CHOLMOD_INT;
  v.xtype = CHOLMOD_REAL;
  v.dtype = CHOLMOD_DOUBLE;
  v.sorted = 1;  // Eigen keeps row indices sorted within a column
  v.packed = 1;
  return v;
}

cholmod_dense DenseView(const double* data, Eigen::Index rows, Eigen::Index cols) {
  cholmod_dense d{};
  d.nrow = static_cast<size_t>(rows);
  d.ncol = static_cast<size_t>(cols);
  d.nzmax = static_cast<size_t>(rows * cols);
  d.d = static_cast<size_t>(rows);
  d.x = const_cast<double*>(data);  // read only (right-hand side)
  d.z = nullptr;
  d.xtype = CHOLMOD_REAL;
  d.dtype = CHOLMOD_DOUBLE;
  return d;
}

class CholmodSolver final : public SparseSolver {
 public:
  CholmodSolver() : state_(std::make_unique<CholmodState>()) {}
  CholmodSolver(CholmodSolver&&) noexcept = default;
  CholmodSolver& operator=(CholmodSolver&&) noexcept = default;
  CholmodSolver(const CholmodSolver&) = delete;
  CholmodSolver& operator=(const CholmodSolver&) = delete;

  void Factorize(const SpMat& A) override {
    CheckSquare(A, name());
    factored_ = false;
    SpMat storage;
    const SpMat& Ac = Compressed(A, &storage);
    cholmod_sparse view = LowerSymmetricView(Ac);
    cholmod_common* c = &state_->common;
    t_cholmod_message.clear();
    if (state_->factor != nullptr && !pattern_.Matches(Ac)) {
      state_->FreeFactor();
      pattern_.Clear();
    }
    if (state_->factor == nullptr) {
      state_->factor = cholmod_analyze(&view, c);
      if (state_->factor == nullptr || c->status < CHOLMOD_OK)
        ThrowCholmod("cholmod_analyze", c->status);
      pattern_.Assign(Ac);
    }
    const int ok = cholmod_factorize(&view, state_->factor, c);
    if (!ok || c->status < CHOLMOD_OK) ThrowCholmod("cholmod_factorize", c->status);
    const cholmod_factor* L = state_->factor;
    if (c->status == CHOLMOD_NOT_POSDEF || L->minor < L->n) {
      // L->minor is the pivot index in the fill-reducing order; Perm maps it back to A.
      const size_t pivot = L->minor;
      const int column =
          L->Perm != nullptr ? static_cast<const int*>(L->Perm)[pivot] : static_cast<int>(pivot);
      const size_t n = L->n;
      state_->FreeFactor();  // a failed numeric factor is not kept
      pattern_.Clear();
      throw NumericalError(
          "CHOLMOD cholmod_factorize: matrix not positive definite: the "
          "Cholesky factorisation failed at column " +
          std::to_string(column) + " of A (pivot " + std::to_string(pivot) + " of " +
          std::to_string(n) + " in the fill-reducing order)");
    }
    n_ = A.rows();
    factored_ = true;
  }

  // The solution is copied out of CHOLMOD's own buffer after the solve, so x may alias b.
  void Solve(const Vec& b, Vec* x) const override {
    CheckSolveSize(b.size(), n_, factored_, name());
    SolveColumns(b.data(), 1, x);
  }

  void Solve(const Mat& B, Mat* X) const override {
    CheckSolveSize(B.rows(), n_, factored_, name());
    if (B.cols() == 0) {
      X->resize(n_, 0);
      return;
    }
    SolveColumns(B.data(), B.cols(), X);
  }

  const char* name() const override { return "CHOLMOD"; }

 private:
  // Solves for `cols` right-hand sides stored column-major at `data`; writes into *out (Vec or
  // Mat, resized).
  template <typename Out>
  void SolveColumns(const double* data, Eigen::Index cols, Out* out) const {
    cholmod_dense rhs = DenseView(data, n_, cols);
    cholmod_common* c = &state_->common;
    t_cholmod_message.clear();
    if (!cholmod_solve2(CHOLMOD_A, state_->factor, &rhs, nullptr, &state_->x, nullptr, &state_->y,
                        &state_->e, c) ||
        c->status < CHOLMOD_OK) {
      ThrowCholmod("cholmod_solve2", c->status);
    }
    const double* result = static_cast<const double*>(state_->x->x);
    if constexpr (std::is_same_v<Out, Vec>) {
      *out = Eigen::Map<const Vec>(result, n_);
    } else {
      *out = Eigen::Map<const Mat>(result, n_, cols);
    }
  }

  std::unique_ptr<CholmodState> state_;
  Pattern pattern_;
  Eigen::Index n_{0};
  bool factored_{false};
};

// ---- UMFPACK ----------------------------------------------------------------------------------

const char* UmfpackStatusMeaning(int status) {
  switch (status) {
    case UMFPACK_OK:
      return "success";
    case UMFPACK_WARNING_singular_matrix:
      return "matrix is singular (a zero pivot)";
    case UMFPACK_WARNING_determinant_underflow:
      return "determinant underflow";
    case UMFPACK_WARNING_determinant_overflow:
      return "determinant overflow";
    case UMFPACK_ERROR_out_of_memory:
      return "out of memory";
    case UMFPACK_ERROR_invalid_Numeric_object:
      return "invalid Numeric object";
    case UMFPACK_ERROR_invalid_Symbolic_object:
      return "invalid Symbolic object";
    case UMFPACK_ERROR_argument_missing:
      return "a required argument is missing";
    case UMFPACK_ERROR_n_nonpositive:
      return "matrix dimension must be > 0";
    case UMFPACK_ERROR_invalid_matrix:
      return "invalid matrix (column pointers or row indices out of range, unsorted or "
             "duplicated)";
    case UMFPACK_ERROR_different_pattern:
      return "pattern changed since the symbolic analysis";
    case UMFPACK_ERROR_invalid_system:
      return "invalid system";
    case UMFPACK_ERROR_invalid_permutation:
      return "invalid permutation";
    case UMFPACK_ERROR_internal_error:
      return "internal error";
    case UMFPACK_ERROR_file_IO:
      return "file I/O error";
    case UMFPACK_ERROR_ordering_failed:
      return "ordering failed";
    default:
      return "unknown status";
  }
}

[[noreturn]] void ThrowUmfpack(const char* call, int status) {
  throw NumericalError(std::string("UMFPACK ") + call + " failed: status " +
                       std::to_string(status) + " (" + UmfpackStatusMeaning(status) + ")");
}

struct UmfpackState {
  void* symbolic{nullptr};
  void* numeric{nullptr};
  UmfpackState() = default;
  ~UmfpackState() {
    FreeNumeric();
    FreeSymbolic();
  }
  UmfpackState(const UmfpackState&) = delete;
  UmfpackState& operator=(const UmfpackState&) = delete;
  void FreeNumeric() {
    if (numeric != nullptr) umfpack_di_free_numeric(&numeric);
  }
  void FreeSymbolic() {
    if (symbolic != nullptr) umfpack_di_free_symbolic(&symbolic);
  }
};

class UmfpackSolver final : public SparseSolver {
 public:
  UmfpackSolver() : state_(std::make_unique<UmfpackState>()) {
    umfpack_di_defaults(control_.data());
  }
  UmfpackSolver(UmfpackSolver&&) noexcept = default;
  UmfpackSolver& operator=(UmfpackSolver&&) noexcept = default;
  UmfpackSolver(const UmfpackSolver&) = delete;
  UmfpackSolver& operator=(const UmfpackSolver&) = delete;

  void Factorize(const SpMat& A) override {
    CheckSquare(A, name());
    factored_ = false;
    state_->FreeNumeric();
    A_ = A;
    A_.makeCompressed();
    const bool same_pattern = state_->symbolic != nullptr && pattern_.Matches(A_);
    const int n = static_cast<int>(A_.rows());
    std::array<double, UMFPACK_INFO> info{};
    if (!same_pattern) {
      state_->FreeSymbolic();
      pattern_.Clear();
      const int status =
          umfpack_di_symbolic(n, n, A_.outerIndexPtr(), A_.innerIndexPtr(), A_.valuePtr(),
                              &state_->symbolic, control_.data(), info.data());
      if (status != UMFPACK_OK) {
        state_->FreeSymbolic();
        ThrowUmfpack("umfpack_di_symbolic", status);
      }
      pattern_.Assign(A_);
    }
    const int status =
        umfpack_di_numeric(A_.outerIndexPtr(), A_.innerIndexPtr(), A_.valuePtr(), state_->symbolic,
                           &state_->numeric, control_.data(), info.data());
    if (status == UMFPACK_WARNING_singular_matrix) {
      state_->FreeNumeric();
      throw NumericalError(
          "UMFPACK umfpack_di_numeric: matrix is singular (status 1: a zero "
          "pivot; " +
          std::to_string(static_cast<long>(info[UMFPACK_UDIAG_NZ])) + " of " + std::to_string(n) +
          " pivots are nonzero)");
    }
    if (status < UMFPACK_OK) {
      state_->FreeNumeric();
      ThrowUmfpack("umfpack_di_numeric", status);
    }
    factored_ = true;
  }

  void Solve(const Vec& b, Vec* x) const override {
    CheckSolveSize(b.size(), A_.rows(), factored_, name());
    Vec out(b.size());
    SolveColumn(b.data(), out.data());
    *x = std::move(out);
  }

  void Solve(const Mat& B, Mat* X) const override {
    CheckSolveSize(B.rows(), A_.rows(), factored_, name());
    Mat out(B.rows(), B.cols());
    for (Eigen::Index j = 0; j < B.cols(); ++j) SolveColumn(B.col(j).data(), out.col(j).data());
    *X = std::move(out);
  }

  const char* name() const override { return "UMFPACK"; }

 private:
  void SolveColumn(const double* b, double* x) const {
    std::array<double, UMFPACK_INFO> info{};
    const int status =
        umfpack_di_solve(UMFPACK_A, A_.outerIndexPtr(), A_.innerIndexPtr(), A_.valuePtr(), x, b,
                         state_->numeric, control_.data(), info.data());
    if (status != UMFPACK_OK) ThrowUmfpack("umfpack_di_solve", status);
  }

  std::unique_ptr<UmfpackState> state_;
  SpMat A_;  // compressed copy: iterative refinement in umfpack_di_solve reads A again
  Pattern pattern_;
  std::array<double, UMFPACK_CONTROL> control_{};
  bool factored_{false};
};

// ---- KLU --------------------------------------------------------------------------------------

const char* KluStatusMeaning(int status) {
  switch (status) {
    case KLU_OK:
      return "success";
    case KLU_SINGULAR:
      return "matrix is singular";
    case KLU_OUT_OF_MEMORY:
      return "out of memory";
    case KLU_INVALID:
      return "invalid input";
    case KLU_TOO_LARGE:
      return "integer overflow (problem too large)";
    default:
      return "unknown status";
  }
}

struct KluState {
  klu_common common{};
  klu_symbolic* symbolic{nullptr};
  klu_numeric* numeric{nullptr};
  KluState() {
    if (!klu_defaults(&common)) throw NumericalError("KLU klu_defaults failed");
  }
  ~KluState() {
    FreeNumeric();
    FreeSymbolic();
  }
  KluState(const KluState&) = delete;
  KluState& operator=(const KluState&) = delete;
  void FreeNumeric() {
    if (numeric != nullptr) klu_free_numeric(&numeric, &common);
  }
  void FreeSymbolic() {
    if (symbolic != nullptr) klu_free_symbolic(&symbolic, &common);
  }
};

class KluSolver final : public SparseSolver {
 public:
  KluSolver() : state_(std::make_unique<KluState>()) {}
  KluSolver(KluSolver&&) noexcept = default;
  KluSolver& operator=(KluSolver&&) noexcept = default;
  KluSolver(const KluSolver&) = delete;
  KluSolver& operator=(const KluSolver&) = delete;

  void Factorize(const SpMat& A) override {
    CheckSquare(A, name());
    factored_ = false;
    state_->FreeNumeric();
    SpMat storage;
    const SpMat& Ac = Compressed(A, &storage);
    const int n = static_cast<int>(Ac.rows());
    // KLU takes non-const pointers but does not modify the matrix.
    int* Ap = const_cast<int*>(Ac.outerIndexPtr());
    int* Ai = const_cast<int*>(Ac.innerIndexPtr());
    double* Ax = const_cast<double*>(Ac.valuePtr());
    klu_common* c = &state_->common;
    if (state_->symbolic == nullptr || !pattern_.Matches(Ac)) {
      state_->FreeSymbolic();
      pattern_.Clear();
      state_->symbolic = klu_analyze(n, Ap, Ai, c);
      if (state_->symbolic == nullptr || c->status != KLU_OK) {
        state_->FreeSymbolic();
        Throw("klu_analyze", c->status);
      }
      pattern_.Assign(Ac);
    }
    state_->numeric = klu_factor(Ap, Ai, Ax, state_->symbolic, c);
    if (state_->numeric == nullptr || c->status != KLU_OK) {
      const int status = c->status;
      state_->FreeNumeric();
      if (status == KLU_SINGULAR) {
        throw NumericalError(
            "KLU klu_factor: matrix is singular (status 1): zero pivot in "
            "column " +
            std::to_string(c->singular_col) + " of A");
      }
      Throw("klu_factor", status);
    }
    n_ = Ac.rows();
    factored_ = true;
  }

  void Solve(const Vec& b, Vec* x) const override {
    CheckSolveSize(b.size(), n_, factored_, name());
    Vec out = b;  // klu_solve overwrites the right-hand side with the solution
    SolveInPlace(out.data(), 1);
    *x = std::move(out);
  }

  void Solve(const Mat& B, Mat* X) const override {
    CheckSolveSize(B.rows(), n_, factored_, name());
    Mat out = B;
    if (out.cols() > 0) SolveInPlace(out.data(), static_cast<int>(out.cols()));
    *X = std::move(out);
  }

  const char* name() const override { return "KLU"; }

 private:
  void SolveInPlace(double* rhs, int cols) const {
    klu_common* c = &state_->common;
    if (!klu_solve(state_->symbolic, state_->numeric, static_cast<int>(n_), cols, rhs, c) ||
        c->status != KLU_OK) {
      Throw("klu_solve", c->status);
    }
  }

  [[noreturn]] static void Throw(const char* call, int status) {
    throw NumericalError(std::string("KLU ") + call + " failed: status " + std::to_string(status) +
                         " (" + KluStatusMeaning(status) + ")");
  }

  std::unique_ptr<KluState> state_;
  Pattern pattern_;
  Eigen::Index n_{0};
  bool factored_{false};
};

}  // namespace

std::unique_ptr<SparseSolver> MakeSparseSolver(SparseSolverKind kind) {
  switch (kind) {
    case SparseSolverKind::kCholmod:
      return std::make_unique<CholmodSolver>();
    case SparseSolverKind::kUmfpack:
      return std::make_unique<UmfpackSolver>();
    case SparseSolverKind::kKlu:
      return std::make_unique<KluSolver>();
  }
  FLEXROD_ASSERT(false && "unknown SparseSolverKind");
  throw std::logic_error("MakeSparseSolver: unknown SparseSolverKind");
}

}  // namespace flexrod::fem
