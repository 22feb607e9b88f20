// fem/eigensolver_arpack.cc — SolveEigenArpack: the generalised symmetric problem K x = λ M x by
// ARPACK-NG's implicitly restarted Lanczos (dsaupd/dseupd, through the ISO-C binding declared
// in <arpack/arpack.h>) in shift-invert mode: mode 3, bmat = 'G', which = 'LM',
// OP = (K − σM)⁻¹ M, B = M. Every ARPACK call of flexrod is made in this file; every info
// code becomes a named ArpackError. The dense oracle (SolveEigenDense) lives in
// fem/eigensolver_dense.cc.
//
// Factorisation of K − σM: CHOLMOD is tried first; it succeeds exactly when K − σM is positive
// definite, i.e. σ is below the lowest eigenvalue. When CHOLMOD reports "not positive
// definite" (σ inside the spectrum, e.g. a frequency-window shift) UMFPACK's LU is used
// instead. Shift-invert Lanczos finds the eigenvalues nearest σ, so with σ inside the spectrum
// completeness is checked with Sturm counts (Sylvester's law of inertia: the number of
// eigenvalues below s equals the number of negative pivots of an LDLᵀ factorisation of
// K − sM; Eigen's SimplicialLDLT, AMD ordering, no pivoting).
//
// Requests:
// * lowest n: one Lanczos run for nev = n when σ is below the spectrum; otherwise nev grows
//   until every eigenvalue below σ (Sturm count) has been found, then the lowest n are kept.
// * window [min_hz, max_hz]: σ at the middle of the window in λ (min_hz > 0) or below the
//   spectrum (min_hz = 0; σ moved further down until K − σM is positive definite). nev starts
//   at the Sturm count of the window plus a margin and is doubled until the run both brackets
//   the window (the found eigenvalues nearest σ reach beyond both edges, so none inside was
//   skipped) and holds at least the Sturm count (so no multiple eigenvalue was missed).
// * small problems (n ≤ 2·nev + 1, where a Krylov space is no cheaper than the full space)
//   go to the dense oracle.
// Results are sorted ascending, M-orthonormal (a Cholesky re-orthonormalisation removes the
// small loss of M-orthogonality after dseupd's purification step), signed with the largest
// entry positive, and every pair's residual is checked.
//
// ARPACK keeps its reverse-communication state in Fortran SAVE variables, so it is not
// re-entrant: Lanczos runs are serialised by a process-wide mutex (factorisations are not).
// The start vector is a fixed pseudo-random sequence, so results do not depend on earlier
// ARPACK calls in the process.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <arpack/arpack.h>

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <numbers>
#include <numeric>
#include <string>
#include <vector>

#include "common/error.h"
#include "fem/eigensolver.h"
#include "fem/sparse_solver.h"

namespace flexrod::fem {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
/// Modes requested beyond the Sturm count of a window, so that the run reaches past its edges.
constexpr int kWindowMargin = 2;
/// Doublings of nev before a request is declared unsolvable.
constexpr int kMaxExpansions = 8;
/// Relative inward nudge of the window edges for the Sturm count (an eigenvalue sitting on an
/// edge may then be found but is not required).
constexpr double kEdgeRelTol = 1e-9;
/// Lower bound of the automatic ncv (header: ncv = min(n, max(2k+1, 20))).
constexpr int kMinLanczosVectors = 20;
/// Largest problem handed to the dense oracle when a sparse request cannot be served.
constexpr int kMaxDenseDofs = 4000;
/// Factor by which the shift moves down when a below-the-spectrum shift is not.
constexpr double kShiftStep = 100.0;
constexpr int kMaxShiftMoves = 8;

std::mutex& ArpackMutex() {
  static std::mutex mutex;
  return mutex;
}

// ---- info codes (ARPACK-NG SRC/dsaupd.f and SRC/dseupd.f, argument INFO) ----------------------

std::string DsaupdInfoMeaning(int info) {
  switch (info) {
    case 0:
      return "normal exit";
    case 1:
      return "maximum number of iterations taken (IPARAM(5) holds the number of converged Ritz "
             "values)";
    case 2:
      return "deprecated informational code (no longer used since ARPACK release 2)";
    case 3:
      return "no shifts could be applied during a cycle of the implicitly restarted Lanczos "
             "iteration; increase ncv relative to nev";
    case -1:
      return "N must be positive";
    case -2:
      return "NEV must be positive";
    case -3:
      return "NCV must be greater than NEV and less than or equal to N";
    case -4:
      return "the maximum number of Arnoldi update iterations must be greater than zero";
    case -5:
      return "WHICH must be one of 'LM', 'SM', 'LA', 'SA' or 'BE'";
    case -6:
      return "BMAT must be 'I' or 'G'";
    case -7:
      return "the private work array WORKL is too short";
    case -8:
      return "the tridiagonal eigenvalue computation (LAPACK dsteqr) failed";
    case -9:
      return "the starting vector is zero";
    case -10:
      return "IPARAM(7) (mode) must be 1, 2, 3, 4 or 5";
    case -11:
      return "IPARAM(7) = 1 and BMAT = 'G' are incompatible";
    case -12:
      return "IPARAM(1) (shift strategy) must be 0 or 1";
    case -13:
      return "NEV and WHICH = 'BE' are incompatible";
    case -9999:
      return "could not build an Arnoldi factorization (IPARAM(5) holds its size); check the "
             "workspace and array storage";
    default:
      return "undocumented info code";
  }
}

std::string DseupdInfoMeaning(int info) {
  switch (info) {
    case 0:
      return "normal exit";
    case -1:
      return "N must be positive";
    case -2:
      return "NEV must be positive";
    case -3:
      return "NCV must be greater than NEV and less than or equal to N";
    case -5:
      return "WHICH must be one of 'LM', 'SM', 'LA', 'SA' or 'BE'";
    case -6:
      return "BMAT must be 'I' or 'G'";
    case -7:
      return "the private work array WORKL is too short";
    case -8:
      return "the tridiagonal eigenvalue computation (LAPACK dsteqr) failed";
    case -9:
      return "the starting vector is zero";
    case -10:
      return "IPARAM(7) (mode) must be 1, 2, 3, 4 or 5";
    case -11:
      return "IPARAM(7) = 1 and BMAT = 'G' are incompatible";
    case -12:
      return "NEV and WHICH = 'BE' are incompatible";
    case -14:
      return "dsaupd found no eigenvalue to sufficient accuracy";
    case -15:
      return "HOWMNY must be 'A' or 'S' when RVEC is true";
    case -16:
      return "HOWMNY = 'S' is not implemented";
    case -17:
      return "dseupd counted a different number of converged Ritz values than dsaupd (data "
             "changed between the two calls)";
    default:
      return "undocumented info code";
  }
}

// ---- small helpers ----------------------------------------------------------------------------

double Square(double x) { return x * x; }
double HzToLambda(double hz) { return Square(kTwoPi * hz); }
double LambdaToHz(double lambda) { return std::sqrt(std::max(lambda, 0.0)) / kTwoPi; }

/// Fixed pseudo-random start vector in [-1, 1): SplitMix64 (Steele, Lea & Flood, OOPSLA 2014),
/// platform independent, so a run does not depend on ARPACK's process-wide random state.
Vec StartVector(Eigen::Index n) {
  std::uint64_t state = 0x5DEECE66DULL;
  Vec v(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    z ^= z >> 31;
    v[i] = 2.0 * (static_cast<double>(z >> 11) * 0x1.0p-53) - 1.0;
  }
  return v;
}

/// Largest absolute column sum = ‖A‖₁ (= ‖A‖∞ for symmetric A; bounds ‖A‖₂).
double NormOne(const SpMat& A) {
  double norm = 0.0;
  for (Eigen::Index j = 0; j < A.outerSize(); ++j) {
    double sum = 0.0;
    for (SpMat::InnerIterator it(A, j); it; ++it) sum += std::abs(it.value());
    norm = std::max(norm, sum);
  }
  return norm;
}

/// Number of eigenvalues λ < shift of K x = λ M x, by Sylvester's law of inertia.
int SturmCount(const SpMat& K, const SpMat& M, double shift) {
  const SpMat A = K - shift * M;
  const Eigen::SimplicialLDLT<SpMat, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt(A);
  if (ldlt.info() != Eigen::Success) {
    throw NumericalError(
        "Sturm count: the LDLT factorisation of K - s M failed at s = " + FormatValue(shift) +
        " rad^2/s^2 (a zero pivot: s is numerically an eigenvalue)");
  }
  return static_cast<int>((ldlt.vectorD().array() < 0.0).count());
}

/// K − σM factorised: CHOLMOD when positive definite, else (unless forbidden) UMFPACK.
struct ShiftedOperator {
  double sigma{0.0};  ///< [rad²/s²]
  std::unique_ptr<SparseSolver>
      solver;                     ///< null when positive definiteness was required and failed
  bool positive_definite{false};  ///< true: σ is below every eigenvalue
};

ShiftedOperator FactorShifted(const SpMat& K, const SpMat& M, double sigma,
                              bool require_positive_definite) {
  const SpMat A = K - sigma * M;
  ShiftedOperator op;
  op.sigma = sigma;
  op.solver = MakeSparseSolver(SparseSolverKind::kCholmod);
  try {
    op.solver->Factorize(A);
    op.positive_definite = true;
    return op;
  } catch (const NumericalError& cholmod_error) {
    op.solver.reset();
    if (require_positive_definite) return op;
    op.solver = MakeSparseSolver(SparseSolverKind::kUmfpack);
    try {
      op.solver->Factorize(A);
    } catch (const NumericalError& lu_error) {
      throw NumericalError(
          "shift-invert eigensolver: K - sigma M is singular at sigma = " + FormatValue(sigma) +
          " rad^2/s^2, i.e. sigma is an eigenvalue (sigma = 0 with rigid-body "
          "modes, for instance); choose another eigen.shift. [" +
          cholmod_error.what() + "] [" + lu_error.what() + "]");
    }
    return op;
  }
}

/// Moves the shift down from `sigma` until K − σM is positive definite (σ below the spectrum).
ShiftedOperator FactorBelowSpectrum(const SpMat& K, const SpMat& M, double sigma) {
  for (int move = 0; move <= kMaxShiftMoves; ++move) {
    ShiftedOperator op = FactorShifted(K, M, sigma, /*require_positive_definite=*/true);
    if (op.positive_definite) return op;
    sigma = move == 0 ? std::min(-1.0, -std::abs(sigma)) : kShiftStep * sigma;
  }
  throw NumericalError("shift-invert eigensolver: no shift down to sigma = " + FormatValue(sigma) +
                       " rad^2/s^2 makes K - sigma M positive definite; K has very negative "
                       "eigenvalues or M is indefinite");
}

/// Ritz pairs of one Lanczos run (unsorted as returned by dseupd).
struct RitzPairs {
  Vec lambda;   ///< [rad²/s²]
  Mat vectors;  ///< columns, M-orthonormal up to dseupd's purification step
  int iterations{0};
  int num_converged{0};
};

/// One shift-invert Lanczos run for the nev eigenvalues nearest op.sigma.
RitzPairs RunLanczos(const SpMat& M, const ShiftedOperator& op, int nev, int ncv, double tol,
                     int max_iterations) {
  const a_int n = static_cast<a_int>(M.rows());
  FLEXROD_ASSERT(0 < nev && nev < ncv && ncv <= n);
  const a_int lworkl = ncv * (ncv + 8);
  Vec resid = StartVector(n);
  Mat V(n, ncv);
  Vec workd(3 * static_cast<Eigen::Index>(n));
  Vec workl(lworkl);
  std::array<a_int, 11> iparam{};
  std::array<a_int, 14> ipntr{};
  iparam[0] = 1;               // ISHIFT: exact shifts
  iparam[2] = max_iterations;  // MXITER
  iparam[3] = 1;               // NB: block size (only 1 is supported)
  iparam[6] = 3;               // MODE: shift-invert
  Vec rhs(n), solution(n);

  std::lock_guard<std::mutex> lock(ArpackMutex());
  a_int ido = 0;
  a_int info = 1;  // RESID holds our start vector
  for (;;) {
    dsaupd_c(&ido, "G", n, "LM", nev, tol, resid.data(), ncv, V.data(), n, iparam.data(),
             ipntr.data(), workd.data(), workl.data(), lworkl, &info);
    if (ido == 99) break;
    const Eigen::Map<const Vec> x(workd.data() + ipntr[0] - 1, n);
    Eigen::Map<Vec> y(workd.data() + ipntr[1] - 1, n);
    if (ido == -1) {  // y = OP x = (K − σM)⁻¹ M x
      rhs.noalias() = M * x;
      op.solver->Solve(rhs, &solution);
      y = solution;
    } else if (ido == 1) {  // y = OP x with M x already in WORKD(IPNTR(3))
      rhs = Eigen::Map<const Vec>(workd.data() + ipntr[2] - 1, n);
      op.solver->Solve(rhs, &solution);
      y = solution;
    } else if (ido == 2) {  // y = B x = M x
      y.noalias() = M * x;
    } else {
      throw ArpackError("dsaupd", info,
                        "unexpected reverse-communication request IDO = " + std::to_string(ido));
    }
  }
  if (info != 0 && info != 1) throw ArpackError("dsaupd", info, DsaupdInfoMeaning(info));
  const int nconv = iparam[4];
  if (nconv < nev) {
    throw ArpackError("dsaupd", info,
                      DsaupdInfoMeaning(info) + "; " + std::to_string(nconv) + " of " +
                          std::to_string(nev) + " Ritz values converged after " +
                          std::to_string(iparam[2]) +
                          " iterations with ncv = " + std::to_string(ncv) +
                          " (raise eigen.max_iterations or eigen.num_lanczos_vectors)");
  }

  std::vector<a_int> select(ncv);  // workspace for HOWMNY = 'A'
  Vec d(nev);
  Mat Z(n, nev);
  a_int info_eupd = 0;
  dseupd_c(/*rvec=*/1, "A", select.data(), d.data(), Z.data(), n, op.sigma, "G", n, "LM", nev, tol,
           resid.data(), ncv, V.data(), n, iparam.data(), ipntr.data(), workd.data(), workl.data(),
           lworkl, &info_eupd);
  if (info_eupd != 0) throw ArpackError("dseupd", info_eupd, DseupdInfoMeaning(info_eupd));

  RitzPairs out;
  out.lambda = d.head(nconv);
  out.vectors = Z.leftCols(nconv);
  out.iterations = iparam[2];
  out.num_converged = nconv;
  return out;
}

/// Sorts the selected pairs ascending, M-orthonormalises them, fixes their sign and checks
/// their residuals.
EigenResult Finalize(const SpMat& K, const SpMat& M, const Vec& lambda, const Mat& vectors,
                     const std::vector<int>& selected, int iterations, int num_converged,
                     double tol) {
  std::vector<int> order = selected;
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return lambda[a] < lambda[b]; });
  const Eigen::Index n = K.rows();
  const Eigen::Index k = static_cast<Eigen::Index>(order.size());
  EigenResult out;
  out.iterations = iterations;
  out.num_converged = num_converged;
  out.eigenvalues.resize(k);
  out.eigenvectors.resize(n, k);
  for (Eigen::Index j = 0; j < k; ++j) {
    out.eigenvalues[j] = lambda[order[j]];
    out.eigenvectors.col(j) = vectors.col(order[j]);
  }
  if (k == 0) return out;

  Mat& X = out.eigenvectors;
  Mat MX = M * X;
  Mat KX = K * X;
  // Gram matrix G = Xᵀ M X = Uᵀ U; X ← X U⁻¹ makes the columns exactly M-orthonormal.
  const Mat G = X.transpose() * MX;
  const Eigen::LLT<Mat> llt(0.5 * (G + G.transpose()));
  if (llt.info() != Eigen::Success) {
    throw NumericalError(
        "shift-invert eigensolver: the computed eigenvectors are linearly "
        "dependent in the M inner product (Gram matrix not positive definite)");
  }
  llt.matrixU().solveInPlace<Eigen::OnTheRight>(X);
  llt.matrixU().solveInPlace<Eigen::OnTheRight>(MX);
  llt.matrixU().solveInPlace<Eigen::OnTheRight>(KX);

  const double norm_k = NormOne(K), norm_m = NormOne(M);
  const double limit = std::max(1e-6, 100.0 * tol);
  for (Eigen::Index j = 0; j < k; ++j) {
    Eigen::Index imax = 0;
    X.col(j).cwiseAbs().maxCoeff(&imax);
    if (X(imax, j) < 0.0) X.col(j) *= -1.0;  // the sign convention of SolveEigenDense
    const double lam = out.eigenvalues[j];
    const double residual = (KX.col(j) - lam * MX.col(j)).norm();
    const double scale = (norm_k + std::abs(lam) * norm_m) * X.col(j).norm();
    if (!(residual <= limit * scale)) {
      throw NumericalError("shift-invert eigensolver: eigenpair " + std::to_string(j) +
                           " (lambda = " + FormatValue(lam) + " rad^2/s^2) has relative residual " +
                           FormatValue(residual / scale) + " > " + FormatValue(limit));
    }
  }
  return out;
}

std::vector<int> AllIndices(Eigen::Index count) {
  std::vector<int> idx(static_cast<size_t>(count));
  std::iota(idx.begin(), idx.end(), 0);
  return idx;
}

/// The k lowest of a set of eigenvalues (indices into lambda).
std::vector<int> LowestIndices(const Vec& lambda, int k) {
  std::vector<int> idx = AllIndices(lambda.size());
  std::stable_sort(idx.begin(), idx.end(), [&](int a, int b) { return lambda[a] < lambda[b]; });
  idx.resize(static_cast<size_t>(std::min<Eigen::Index>(k, lambda.size())));
  return idx;
}

int NumLanczosVectors(const EigenRequest& request, int nev, int n) {
  if (request.num_lanczos_vectors > nev) return std::min(request.num_lanczos_vectors, n);
  return std::min(n, std::max(2 * nev + 1, kMinLanczosVectors));
}

/// True when ARPACK can serve nev modes of an n-dof problem better than the dense oracle.
bool LanczosFits(int nev, int n) { return 2 * nev + 1 < n; }

[[noreturn]] void ThrowTooLargeForDense(int n, const std::string& what) {
  throw NumericalError("shift-invert eigensolver: " + what + " needs more Lanczos vectors than " +
                       std::to_string(n) + " dofs allow, and the problem is too large (> " +
                       std::to_string(kMaxDenseDofs) + " dofs) for the dense solver");
}

// ---- requests ---------------------------------------------------------------------------------

void ValidateRequest(const SpMat& K, const SpMat& M, const EigenRequest& r, bool window) {
  if (K.rows() != K.cols() || M.rows() != M.cols() || K.rows() != M.rows() || K.rows() == 0) {
    throw InputError("K, M",
                     std::to_string(K.rows()) + "x" + std::to_string(K.cols()) + ", " +
                         std::to_string(M.rows()) + "x" + std::to_string(M.cols()),
                     "must be square, non-empty and of the same size");
  }
  const int n = static_cast<int>(K.rows());
  Require(std::isfinite(r.shift), "eigen.shift", r.shift, "must be finite");
  Require(r.tolerance >= 0.0 && r.tolerance < 1.0, "eigen.tolerance", r.tolerance,
          "must be in [0, 1) (0 = machine precision)");
  Require(r.max_iterations >= 1, "eigen.max_iterations", r.max_iterations, "must be >= 1");
  Require(r.num_lanczos_vectors >= 0 && r.num_lanczos_vectors <= n, "eigen.num_lanczos_vectors",
          r.num_lanczos_vectors,
          "must be 0 (automatic) or at most the number of dofs (" + std::to_string(n) + ")");
  if (window) {
    Require(std::isfinite(r.min_hz) && r.min_hz >= 0.0, "eigen.min_hz", r.min_hz, "must be >= 0");
    Require(std::isfinite(r.max_hz) && r.max_hz > r.min_hz, "eigen.max_hz", r.max_hz,
            "must be > eigen.min_hz = " + FormatValue(r.min_hz) + " Hz");
    return;
  }
  Require(r.num_modes >= 1, "eigen.num_modes", r.num_modes, "must be >= 1");
  Require(r.num_modes < n, "eigen.num_modes", r.num_modes,
          "must be < the number of dofs (" + std::to_string(n) + ")");
  Require(r.num_lanczos_vectors == 0 || r.num_lanczos_vectors > r.num_modes,
          "eigen.num_lanczos_vectors", r.num_lanczos_vectors,
          "must be 0 (automatic) or > eigen.num_modes = " + std::to_string(r.num_modes));
}

EigenResult SolveLowest(const SpMat& K, const SpMat& M, const EigenRequest& request) {
  const int n = static_cast<int>(K.rows());
  const int k = request.num_modes;
  const auto dense = [&]() {
    const EigenResult d = SolveEigenDense(Mat(K), Mat(M), k);
    return Finalize(K, M, d.eigenvalues, d.eigenvectors, AllIndices(d.eigenvalues.size()), 0,
                    d.num_converged, request.tolerance);
  };
  if (!LanczosFits(k, n)) return dense();

  const ShiftedOperator op = FactorShifted(K, M, request.shift, false);
  // With σ inside the spectrum the run must hold every eigenvalue below σ; then the eigenvalues
  // it found are all those below σ + r, and its k lowest are the k lowest of the problem.
  const int below = op.positive_definite ? 0 : SturmCount(K, M, op.sigma);
  int nev = k + below;
  int iterations = 0;
  for (int expansion = 0;; ++expansion) {
    if (!LanczosFits(nev, n)) {
      if (n <= kMaxDenseDofs) return dense();
      ThrowTooLargeForDense(n, "the lowest " + std::to_string(k) + " modes with eigen.shift = " +
                                   FormatValue(op.sigma) + " rad^2/s^2");
    }
    const RitzPairs run = RunLanczos(M, op, nev, NumLanczosVectors(request, nev, n),
                                     request.tolerance, request.max_iterations);
    iterations += run.iterations;
    const int found_below = static_cast<int>((run.lambda.array() < op.sigma).count());
    if (found_below >= below) {
      return Finalize(K, M, run.lambda, run.vectors, LowestIndices(run.lambda, k), iterations,
                      run.num_converged, request.tolerance);
    }
    if (expansion == kMaxExpansions) {
      throw NumericalError("shift-invert eigensolver: found " + std::to_string(found_below) +
                           " of the " + std::to_string(below) +
                           " eigenvalues below eigen.shift = " + FormatValue(op.sigma) +
                           " rad^2/s^2 with nev = " + std::to_string(nev) +
                           "; use a shift below the lowest eigenvalue");
    }
    nev *= 2;
  }
}

EigenResult SolveWindow(const SpMat& K, const SpMat& M, const EigenRequest& request) {
  const int n = static_cast<int>(K.rows());
  const bool from_zero = request.min_hz == 0.0;
  const double lambda_lo = HzToLambda(request.min_hz);
  const double lambda_hi = HzToLambda(request.max_hz);
  const auto in_window = [&](double lambda) {
    const double f = LambdaToHz(lambda);
    return f >= request.min_hz && f <= request.max_hz;
  };
  const auto select = [&](const Vec& lambda) {
    std::vector<int> idx;
    for (Eigen::Index i = 0; i < lambda.size(); ++i)
      if (in_window(lambda[i])) idx.push_back(static_cast<int>(i));
    return idx;
  };
  const auto dense = [&]() {
    const EigenResult d = SolveEigenDense(Mat(K), Mat(M));
    return Finalize(K, M, d.eigenvalues, d.eigenvectors, select(d.eigenvalues), 0, d.num_converged,
                    request.tolerance);
  };

  // Modes strictly inside the window (f = 0 counts as inside when min_hz = 0).
  const int expected =
      std::max(0, SturmCount(K, M, lambda_hi * (1.0 - kEdgeRelTol)) -
                      (from_zero ? 0 : SturmCount(K, M, lambda_lo * (1.0 + kEdgeRelTol))));
  int nev = expected + kWindowMargin;
  if (!LanczosFits(nev, n)) {
    if (n <= kMaxDenseDofs) return dense();
    ThrowTooLargeForDense(n, "the frequency window");
  }

  ShiftedOperator op;
  if (from_zero) {
    op = FactorBelowSpectrum(K, M, request.shift);
  } else {
    // σ at the middle of the window in λ; moved slightly if it hits an eigenvalue exactly.
    const double half_width = 0.5 * (lambda_hi - lambda_lo);
    double sigma = lambda_lo + half_width;
    for (int attempt = 0;; ++attempt) {
      try {
        op = FactorShifted(K, M, sigma, false);
        break;
      } catch (const NumericalError&) {
        if (attempt == 3) throw;
        sigma += 1e-3 * half_width;
      }
    }
  }

  int iterations = 0;
  for (int expansion = 0;; ++expansion) {
    if (!LanczosFits(nev, n)) {
      if (n <= kMaxDenseDofs) return dense();
      ThrowTooLargeForDense(n, "the frequency window");
    }
    const RitzPairs run = RunLanczos(M, op, nev, NumLanczosVectors(request, nev, n),
                                     request.tolerance, request.max_iterations);
    iterations += run.iterations;
    // The run holds every eigenvalue within r of σ; the window is covered when it lies inside
    // (σ − r, σ + r) (the low side is automatic when σ is below the spectrum).
    const double r = (run.lambda.array() - op.sigma).abs().maxCoeff();
    const bool covered =
        op.sigma + r > lambda_hi && (op.positive_definite || op.sigma - r < lambda_lo);
    const std::vector<int> found = select(run.lambda);
    if (covered && static_cast<int>(found.size()) >= expected) {
      return Finalize(K, M, run.lambda, run.vectors, found, iterations, run.num_converged,
                      request.tolerance);
    }
    if (expansion == kMaxExpansions) {
      throw NumericalError(
          "shift-invert eigensolver: the window " + FormatValue(request.min_hz) + ".." +
          FormatValue(request.max_hz) + " Hz holds " + std::to_string(expected) +
          " modes (Sturm count); " + std::to_string(found.size()) +
          " found with nev = " + std::to_string(nev) + (covered ? "" : ", window not bracketed"));
    }
    nev = std::max(2 * nev, expected + kWindowMargin);
  }
}

}  // namespace

EigenResult SolveEigenArpack(const SpMat& K, const SpMat& M, const EigenRequest& request) {
  const bool window = request.max_hz > 0.0 || request.min_hz > 0.0;
  ValidateRequest(K, M, request, window);
  return window ? SolveWindow(K, M, request) : SolveLowest(K, M, request);
}

}  // namespace flexrod::fem
