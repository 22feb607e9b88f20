// multibody/ida_options.cc — the integrator's options and their checks, the DaeSystem
// defaults, and IDA's return flags as names and hints.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <ida/ida.h>

#include <cmath>
#include <string>

#include "common/error.h"
#include "multibody/ida_integrator.h"

namespace flexrod::multibody {

// ---- DaeSystem defaults -------------------------------------------------------------------------
void DaeSystem::AbsoluteToleranceScales(double* scales) const {
  for (int i = 0; i < size(); ++i) scales[i] = 1.0;
}

void DaeSystem::RelativeToleranceCaps(double* caps) const {
  for (int i = 0; i < size(); ++i) caps[i] = std::numeric_limits<double>::infinity();
}

void DaeSystem::StepScaledWeightMask(double* mask) const {
  DifferentialMask(mask);
  for (int i = 0; i < size(); ++i) mask[i] = mask[i] == 0.0 ? 1.0 : 0.0;
}

int DaeSystem::JacobianAndDerivativePart(double t, double cj, const double* y, const double* yp,
                                         double* jac, double* dfdyp) {
  const int rc = Jacobian(t, cj, y, yp, jac);
  if (rc != 0) return rc;
  const int rc1 = Jacobian(t, cj + 1.0, y, yp, dfdyp);
  const size_t nn = static_cast<size_t>(size()) * static_cast<size_t>(size());
  for (size_t i = 0; i < nn; ++i) dfdyp[i] -= jac[i];
  return rc1;
}

SparsityPattern DaeSystem::JacobianPattern() const {
  SparsityPattern p;
  const int n = size();
  p.size = n;
  p.col_ptr.resize(n + 1);
  p.row_index.reserve(static_cast<size_t>(n) * n);
  for (int c = 0; c <= n; ++c) p.col_ptr[c] = static_cast<int64_t>(c) * n;
  for (int c = 0; c < n; ++c)
    for (int r = 0; r < n; ++r) p.row_index.push_back(r);
  return p;
}

const char* ToString(LinearSolverKind kind) {
  switch (kind) {
    case LinearSolverKind::kAuto:
      return "auto";
    case LinearSolverKind::kDense:
      return "dense";
    case LinearSolverKind::kKlu:
      return "klu";
  }
  return "?";
}

void IntegratorOptions::Validate() const {
  // Below 1e-14 a relative error is under the doubles' reach; below 1e-20 the error weights
  // 1 / (rel_tol |y| + abs_tol) of components at zero overflow IDA's norms.
  Require(rel_tol >= 1e-14 && rel_tol < 1.0, "integrator.rel_tol", rel_tol,
          "must be in [1e-14, 1)");
  Require(abs_tol >= 1e-20 && std::isfinite(abs_tol), "integrator.abs_tol", abs_tol,
          "must be finite and >= 1e-20");
  RequireNonNegative("integrator.max_step", max_step);
  RequireNonNegative("integrator.initial_step", initial_step);
  Require(max_order >= 1 && max_order <= 5, "integrator.max_order", max_order, "must be 1..5");
  Require(max_nonlinear_iterations >= 1, "integrator.max_nonlinear_iterations",
          max_nonlinear_iterations, "must be >= 1");
  Require(max_convergence_failures >= 1, "integrator.max_convergence_failures",
          max_convergence_failures, "must be >= 1");
  Require(max_error_test_failures >= 1, "integrator.max_error_test_failures",
          max_error_test_failures, "must be >= 1");
  Require(nonlinear_convergence_coefficient > 0.0 && nonlinear_convergence_coefficient < 1.0,
          "integrator.nonlinear_convergence_coefficient", nonlinear_convergence_coefficient,
          "must be in (0, 1)");
  RequireNonNegative("integrator.jacobian_refresh_cj_change", jacobian_refresh_cj_change);
  Require(jacobian_reuse_steps >= 0, "integrator.jacobian_reuse_steps", jacobian_reuse_steps,
          "must be >= 0");
  Require(dense_fill_threshold >= 0.0 && dense_fill_threshold <= 1.0,
          "integrator.dense_fill_threshold", dense_fill_threshold, "must be in [0, 1]");
}

std::string IdaFlagName(int flag) {
  char* name = IDAGetReturnFlagName(flag);
  std::string out = name != nullptr ? name : "IDA flag " + std::to_string(flag);
  std::free(name);
  return out;
}

std::string IdaFailureHint(int flag) {
  switch (flag) {
    case IDA_TOO_MUCH_ACC:
      return "the requested accuracy is beyond machine precision: loosen rel_tol / abs_tol";
    case IDA_ERR_FAIL:
      return "repeated error-test failures: tighten tolerances or reduce max_step; look for a "
             "discontinuity no event catches, or an inconsistent restart";
    case IDA_CONV_FAIL:
      return "Newton iterations do not converge: reduce max_step or tighten tolerances; check "
             "the Jacobian";
    case IDA_LINIT_FAIL:
    case IDA_LSETUP_FAIL:
    case IDA_LSOLVE_FAIL:
      return "linear solver failure: the iteration matrix is singular";
    case IDA_RES_FAIL:
    case IDA_REP_RES_ERR:
      return "the residual keeps failing (recoverable errors or non-finite values)";
    case IDA_TOO_MUCH_WORK:
      return "too many steps: raise the step budget or loosen tolerances";
    default:
      return "tighten tolerances / reduce max_step / check the model inputs";
  }
}

}  // namespace flexrod::multibody
