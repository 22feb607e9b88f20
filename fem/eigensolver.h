// fem/eigensolver.h — generalised symmetric eigenproblem K x = λ M x (λ = ω²):
// ARPACK (dsaupd/dseupd) in shift-invert mode with a SuiteSparse factorisation of K − σM
// (CHOLMOD when K − σM is positive definite, i.e. σ below the lowest eigenvalue, UMFPACK
// otherwise), and a dense Eigen solver for small problems that is also the test oracle.
// Every ARPACK info code becomes a named ArpackError.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <string>

#include "common/eigen.h"
#include "common/error.h"

namespace flexrod::fem {

struct EigenRequest {
  int num_modes{10};   ///< lowest-n request (used when band is not set), >= 1
  double shift{-1.0};  ///< σ [rad²/s²]; negative keeps K − σM positive definite for K ≥ 0
  /// Optional frequency window [Hz]: when max_hz > 0, all modes with min_hz ≤ f ≤ max_hz.
  double min_hz{0.0};
  double max_hz{0.0};
  double tolerance{1e-10};  ///< ARPACK tol; 0 = machine precision (1e-10: same eigenvalues to
                            ///< 1e-14, 2-5x faster)
  int max_iterations{1000};
  int num_lanczos_vectors{0};  ///< ncv; 0 = automatic min(n, max(2k+1, 20))
};

struct EigenResult {
  Vec eigenvalues;   ///< λ = ω² [rad²/s²], ascending
  Mat eigenvectors;  ///< columns, M-orthonormal (xᵀ M x = 1)
  int iterations{0};
  int num_converged{0};
  Vec frequencies_hz() const;  ///< f = sqrt(max(λ,0)) / 2π [Hz]
};

class ArpackError : public NumericalError {
 public:
  ArpackError(const std::string& routine, int info, const std::string& meaning)
      : NumericalError("ARPACK " + routine + " info = " + std::to_string(info) + ": " + meaning),
        info_(info) {}
  int info() const { return info_; }

 private:
  int info_;
};

/// Sparse shift-invert Lanczos. K, M symmetric (full storage), M positive semi-definite.
EigenResult SolveEigenArpack(const SpMat& K, const SpMat& M, const EigenRequest& request);
/// Dense oracle: all eigenpairs (or the lowest request.num_modes) of the same problem.
EigenResult SolveEigenDense(const Mat& K, const Mat& M, int num_modes = -1);

}  // namespace flexrod::fem
