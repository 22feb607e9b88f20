// fem/eigensolver_dense.cc — dense generalised symmetric eigensolver (the test oracle and the
// solver for small problems) and EigenResult::frequencies_hz. The ARPACK solver lives in
// fem/eigensolver_arpack.cc.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "fem/eigensolver.h"

namespace flexrod::fem {

Vec EigenResult::frequencies_hz() const {
  Vec f(eigenvalues.size());
  for (Eigen::Index i = 0; i < eigenvalues.size(); ++i)
    f[i] = std::sqrt(std::max(eigenvalues[i], 0.0)) / (2.0 * std::numbers::pi);
  return f;
}

EigenResult SolveEigenDense(const Mat& K, const Mat& M, int num_modes) {
  FLEXROD_ASSERT(K.rows() == K.cols() && M.rows() == M.cols() && K.rows() == M.rows());
  const Eigen::Index n = K.rows();
  if (num_modes == 0 || num_modes > n) {
    throw InputError("num_modes", std::to_string(num_modes),
                     "must be in [1, " + std::to_string(n) + "] (or negative for all modes)");
  }
  EigenResult out;
  if (n == 0) {
    out.eigenvalues.resize(0);
    out.eigenvectors.resize(0, 0);
    return out;
  }
  // Symmetrise: callers pass assembled matrices that are symmetric only up to round-off.
  const Mat Ks = 0.5 * (K + K.transpose());
  const Mat Ms = 0.5 * (M + M.transpose());
  // Reduce to a standard problem with M = L Lᵀ: C = L⁻¹ K L⁻ᵀ, x = L⁻ᵀ y. Done here rather
  // than with Eigen's GeneralizedSelfAdjointEigenSolver, which does not report a failed
  // Cholesky factorisation of M.
  const Eigen::LLT<Mat> chol(Ms);
  if (chol.info() != Eigen::Success) {
    throw NumericalError(
        "dense generalised eigensolver: the mass matrix is not positive definite on the "
        "given dofs (Cholesky factorisation failed); fix or remove massless dofs");
  }
  Mat C = Ks;
  chol.matrixL().solveInPlace<Eigen::OnTheLeft>(C);
  chol.matrixU().solveInPlace<Eigen::OnTheRight>(C);
  C = 0.5 * (C + C.transpose());
  Eigen::SelfAdjointEigenSolver<Mat> es(C, Eigen::ComputeEigenvectors);
  if (es.info() != Eigen::Success) {
    throw NumericalError("dense symmetric eigensolver did not converge (Eigen info = " +
                         std::to_string(static_cast<int>(es.info())) + ")");
  }
  Mat vectors = es.eigenvectors();
  chol.matrixU().solveInPlace(vectors);
  const Eigen::Index k = num_modes < 0 ? n : num_modes;
  out.eigenvalues = es.eigenvalues().head(k);  // Eigen returns them ascending
  out.eigenvectors = vectors.leftCols(k);
  // yᵀy = 1 gives xᵀ M x = 1; fix the sign (largest-magnitude entry positive) so that
  // results are reproducible across platforms and runs.
  for (Eigen::Index j = 0; j < k; ++j) {
    Eigen::Index imax = 0;
    out.eigenvectors.col(j).cwiseAbs().maxCoeff(&imax);
    if (out.eigenvectors(imax, j) < 0.0) out.eigenvectors.col(j) *= -1.0;
  }
  out.iterations = 0;  // direct method
  out.num_converged = static_cast<int>(k);
  return out;
}

}  // namespace flexrod::fem
