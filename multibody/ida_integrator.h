// multibody/ida_integrator.h — a thin RAII wrapper over SUNDIALS IDA (6.4) for a generic
// DAE F(t, y, ẏ) = 0: context, serial vectors, dense or KLU linear solver, analytic
// Jacobian, root finding, one-step integration with dense output (IDAGetDky), re-initialisation
// after events, statistics and time spent in residual / Jacobian / linear solver. Every IDA
// call is checked; a failing flag throws NumericalError naming the call and the flag. The
// wrapper knows nothing about mechanisms: it sees only DaeSystem. No other file calls IDA.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <array>
#include <cstdint>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "common/error.h"

namespace flexrod::multibody {

/// Compressed-sparse-column pattern of an N×N matrix.
struct SparsityPattern {
  int64_t size{0};                 ///< N
  std::vector<int64_t> col_ptr;    ///< N + 1 entries
  std::vector<int64_t> row_index;  ///< nnz entries, ascending within each column
  int64_t nnz() const { return static_cast<int64_t>(row_index.size()); }
};

/// A DAE F(t, y, ẏ) = 0 of fixed size. Callback return codes: 0 success, > 0 recoverable
/// (IDA retries with a smaller step), < 0 unrecoverable. Exceptions thrown by callbacks are
/// caught, reported to IDA as unrecoverable, and rethrown from IdaIntegrator::Step.
class DaeSystem {
 public:
  virtual ~DaeSystem() = default;
  virtual int size() const = 0;
  virtual int num_roots() const { return 0; }
  /// id[i] = 1 for an unknown under the local error test (differential), 0 otherwise
  /// (algebraic unknowns, and any unknown the system wants outside the error test).
  virtual void DifferentialMask(double* id) const = 0;
  /// mask[i] = 1 for unknowns whose error weight is multiplied by the step size when
  /// IntegratorOptions::scale_algebraic_weights_by_step is set (index-2 algebraic unknowns).
  /// Default: every unknown with id = 0.
  virtual void StepScaledWeightMask(double* mask) const;
  /// Per-unknown multiplier of the absolute tolerance (default 1).
  virtual void AbsoluteToleranceScales(double* scales) const;
  /// Per-unknown cap on the magnitude the relative tolerance applies to: the error weight is
  /// 1/(rel_tol·min(|y_i|, cap_i) + abs_tol_i). Default +∞ (IDA's rule).
  virtual void RelativeToleranceCaps(double* caps) const;
  virtual int Residual(double t, const double* y, const double* yp, double* r) = 0;
  /// Adds dF/dy + cj dF/dẏ into the zeroed column-major N×N array jac.
  virtual int Jacobian(double t, double cj, const double* y, const double* yp, double* jac) = 0;
  /// As Jacobian, and adds dF/dẏ alone into the zeroed N×N array dfdyp: the iteration matrix
  /// for another c_j is then jac + (c_j' − c_j) dfdyp, without an evaluation
  /// (IntegratorOptions::jacobian_reuse_steps). Default: a second Jacobian at c_j + 1, minus
  /// the first.
  virtual int JacobianAndDerivativePart(double t, double cj, const double* y, const double* yp,
                                        double* jac, double* dfdyp);
  /// Non-zero pattern of the Jacobian (used by the sparse solver only). Default: dense.
  virtual SparsityPattern JacobianPattern() const;
  virtual int Roots(double /*t*/, const double* /*y*/, const double* /*yp*/, double* /*g*/) {
    return 0;
  }
};

enum class LinearSolverKind { kAuto, kDense, kKlu };
const char* ToString(LinearSolverKind kind);

/// kAuto selects the dense LU (ida_dense_solver.h) when the iteration matrix's sparsity
/// pattern fills at least this fraction of its n² entries, KLU below. The Craig–Bampton and
/// full-FE rods (fill 0.30 to 0.42) ran in fewer instructions on the dense LU at every size
/// measured, the exact rod (a body per node, fill 0.04 to 0.07) on KLU (callgrind, whole runs;
/// the figures are in commit deb7c9a's message).
inline constexpr double kDenseFillThreshold = 0.2;
/// An iteration-matrix entry outside the sparsity pattern (a model bug) is looked for at the
/// first Jacobian and every this many.
inline constexpr long kPatternCheckInterval = 64;

/// Default of IntegratorOptions::jacobian_reuse_steps. Measured (CPU, minimum of 3 runs, against
/// 0): the exudyn-match clearance case 2.24 -> 2.03 s (53 182 -> about 12 000 evaluations), its
/// ideal case 0.121 -> 0.117 s, the main job 1.84 -> 1.79 s, bench_mb_rigid_crank's full-FE rod
/// 4.6 -> 2.5 s (dense) and 5.7 -> 3.5 s (KLU). 50 steps gave the same on the first three but
/// more than twice the steps on that benchmark's 8-mode slider-crank, whose steps of 2 ms turn
/// the frame several degrees each: an old matrix converges the Newton iteration less far, and
/// IDA's error estimate, which sees the remainder, then does not let the step double.
inline constexpr int kJacobianReuseSteps = 20;

struct IntegratorOptions {
  double rel_tol{1e-6};              ///< relative tolerance [-], in (0, 1)
  double abs_tol{1e-8};              ///< absolute tolerance (scaled per unknown by the system) [SI]
  double max_step{0.0};              ///< maximum step [s]; 0 = unlimited
  double initial_step{0.0};          ///< first step [s]; 0 = IDA's estimate
  int max_order{5};                  ///< BDF order 1..5
  int max_nonlinear_iterations{4};   ///< Newton iterations per step (IDA default 4)
  int max_convergence_failures{10};  ///< per step (IDA default 10)
  int max_error_test_failures{10};   ///< per step (IDA default 10)
  /// Newton convergence-test coefficient (IDASetNonlinConvCoef), in (0, 1); IDA default 0.33.
  double nonlinear_convergence_coefficient{0.33};
  /// Re-factor the iteration matrix when |c_j/c_j,old − 1| exceeds this (IDASetDeltaCjLSetup),
  /// >= 0; IDA default 0.25.
  double jacobian_refresh_cj_change{0.25};
  /// IDA evaluates the Jacobian whenever it sets up the iteration matrix dF/dy + c_j dF/dẏ,
  /// which it does at every change of c_j beyond jacobian_refresh_cj_change. With this > 0,
  /// a set-up within this many steps of the last evaluation forms the matrix for the new c_j
  /// from the saved dF/dy and dF/dẏ instead (modified Newton, as CVODE keeps its Jacobian over
  /// a number of steps, CVodeSetJacEvalFrequency, and forms I − γJ anew), and tells the
  /// Newton solver the matrix is not current: a Newton failure on it is retried on a fresh
  /// evaluation before the step is cut, as a failure on an old matrix is. The first set-up
  /// after a (re-)initialisation always evaluates. The solution is decided by the residual and
  /// the convergence test, not the matrix. 0: evaluate at every set-up (IDA's rule).
  int jacobian_reuse_steps{kJacobianReuseSteps};
  LinearSolverKind linear_solver{LinearSolverKind::kAuto};
  /// kAuto: the dense LU from this fraction of non-zeros in the iteration matrix on, KLU below.
  double dense_fill_threshold{kDenseFillThreshold};
  bool suppress_algebraic{true};  ///< exclude algebraic unknowns from the error test
  /// Multiply the error weights of the unknowns in DaeSystem::StepScaledWeightMask (index-2
  /// algebraic unknowns) by the step size h. Their Newton
  /// corrections carry round-off noise that grows like 1/h for index-2 multipliers (GGL λ,
  /// μ), which otherwise stalls the Newton convergence test at small steps; RADAU5 scales
  /// index-2 components by h in the same way (Hairer & Wanner, Solving ODEs II, 2nd ed.,
  /// §VII.8). Implemented through IDAWFtolerances. Affects only the Newton test when
  /// suppress_algebraic is set.
  bool scale_algebraic_weights_by_step{true};
  /// Measure the wall time of residuals, Jacobians and linear solves (IntegratorStats::
  /// residual_seconds, ...; zero otherwise). Two clock reads per call: about 2 % of a rigid
  /// rig's run, whose callbacks take microseconds.
  bool time_calls{false};
  /// After each step, count the unknown under error control with the largest weighted local
  /// error estimate |e_i| w_i (IDAGetEstLocalErrors, IDAGetErrWeights): the unknown that sets
  /// the step size (IdaIntegrator::step_limiting_counts). About 4 N operations a step.
  bool count_step_limiting{false};
  /// Throws InputError naming integrator.<field>.
  void Validate() const;
};

struct IntegratorStats {
  long steps{0};
  long residual_evaluations{0};
  long jacobian_evaluations{0};  ///< evaluations of dF/dy (DaeSystem::Jacobian)
  /// iteration matrices set up and factored: the evaluations plus the matrices formed for a new
  /// c_j from saved parts (IntegratorOptions::jacobian_reuse_steps)
  long matrix_setups{0};
  long nonlinear_iterations{0};
  long nonlinear_convergence_failures{0};
  long error_test_failures{0};
  /// [k]: steps taken at BDF order k (k = 1..5; [0] unused). IDA starts at order 1 after every
  /// (re-)initialisation and raises the order after steps without a failure; a run held there
  /// gets a note (CaughtStepControlNote, multibody/simulate.h).
  std::array<long, 6> steps_by_order{};
  long roots_found{0};
  long reinitialisations{0};
  int last_order{0};
  double last_step{0.0};  ///< [s]
  // Zero unless IntegratorOptions::time_calls:
  double residual_seconds{0.0};      ///< wall time inside the residual [s]
  double jacobian_seconds{0.0};      ///< wall time inside the Jacobian (incl. sparse gather) [s]
  double linear_solve_seconds{0.0};  ///< wall time in linear-solver setup (factor) + solve [s]
};

/// IDASolve gave up (error-test or convergence failures, too much accuracy requested, a
/// callback failed unrecoverably ...). Carries the IDA flag, its name and the time reached.
class IntegratorFailure : public NumericalError {
 public:
  IntegratorFailure(const std::string& what, int flag, std::string flag_name, double t)
      : NumericalError(what), flag_(flag), flag_name_(std::move(flag_name)), t_(t) {}
  int flag() const { return flag_; }
  const std::string& flag_name() const { return flag_name_; }
  double time() const { return t_; }

 private:
  int flag_;
  std::string flag_name_;
  double t_;
};

/// kRootStall: IDA cannot continue past a root function that stays exactly zero after a root
/// return; the caller re-initialises at StepResult::t (the solution is the last one returned).
enum class StepOutcome { kStep, kRoot, kStopTime, kRootStall };
struct StepResult {
  StepOutcome outcome{StepOutcome::kStep};
  double t{0.0};  ///< time returned by IDA (the root time for kRoot)
};

/// Name of an IDA return flag ("IDA_ERR_FAIL", ...).
std::string IdaFlagName(int flag);
/// What to try after IDASolve failed with this flag (generic DAE advice).
std::string IdaFailureHint(int flag);

class IdaIntegrator {
 public:
  /// The system must outlive the integrator.
  IdaIntegrator(DaeSystem* system, const IntegratorOptions& options);
  ~IdaIntegrator();
  IdaIntegrator(const IdaIntegrator&) = delete;
  IdaIntegrator& operator=(const IdaIntegrator&) = delete;

  /// First call: IDAInit and all set-up; later calls: IDAReInit (BDF history restarts at
  /// order 1; statistics keep accumulating). (y0, yp0) should be consistent.
  void Initialize(double t0, const double* y0, const double* yp0);
  void SetStopTime(double t_stop);
  /// One internal step (IDA_ONE_STEP) towards tout; returns a step, a located root or the
  /// stop time. Throws IntegratorFailure if IDA gives up, NumericalError on misuse.
  StepResult Step(double tout);
  /// Dense output: k = 0 state, k = 1 derivative, at t within the last step.
  void DenseOutput(double t, int k, double* out);
  /// Caches IDA's interpolating polynomial of the last step (degree k = k_used) from IDA's
  /// memory record, its modified divided differences φ_j and step sums ψ_j:
  ///   y(t) = Σ_j c_j(t) φ_j,  c_0 = 1,  c_j = c_{j−1} (t − t_n + ψ_{j−2}) / ψ_{j−1}  (ψ_{−1} = 0),
  /// and ẏ(t) = Σ_j c_j'(t) φ_j: the sum IDAGetDky forms (IDA user guide, "Mathematical
  /// considerations"). A step expected to hold fewer than four evaluations (its length over
  /// `evaluation_interval` [s]; 0: few) is evaluated in that form: weights per evaluation, no work
  /// per step (a few samples or a peak search per step, the common case). A longer one is
  /// evaluated in the power form y(t) = Σ_m T_m (t − t_n)^m, its rows built here once, then by
  /// Horner's rule (a rigid run at 100 kHz has hundreds of samples per step). Either form agrees
  /// with IDAGetDky to round-off and is φ_0 exactly at t_n. Valid until the next Step or
  /// Initialize (φ is read in place). EvaluateStepPolynomial then gives y(t) and ẏ(t) for any t
  /// of the last step without calling IDA.
  void CacheStepPolynomial(double evaluation_interval = 0.0);
  /// Component i of y(t) and ẏ(t) goes to y[into[i]] and yp[into[i]] (into = nullptr: to
  /// y[i], yp[i]), so that a caller with a larger layout (PrescribedMotion) needs no copy.
  void EvaluateStepPolynomial(double t, double* y, double* yp, const int* into = nullptr) const;
  /// y_i(t) alone (no ẏ) for the components i in [begin, end), written to y[into[i]]: the
  /// numbers EvaluateStepPolynomial writes there, for a caller that needs a few unknowns at many
  /// times of one step (the impact log's peak search reads one joint's two bodies).
  void EvaluateStepPolynomialValues(double t, int begin, int end, double* y, const int* into) const;
  /// Validity interval [t_n − h_used, t_n] of the cached polynomial.
  double polynomial_start() const { return poly_t0_; }
  double polynomial_end() const { return poly_tn_; }
  /// State and derivative returned by the last Step.
  const double* y() const;
  const double* yp() const;
  /// For the last kRoot: rootsfound[i] ∈ {−1, 0, +1} (num_roots entries).
  void RootInfo(int* roots_found);
  /// Index of the unknown with the largest weighted local error estimate, and that value.
  void WorstLocalError(int* index, double* weighted_error);
  /// IntegratorOptions::count_step_limiting: for each unknown, the steps after which it had the
  /// largest weighted local error estimate among the unknowns under error control (their sum
  /// is the number of steps); empty otherwise.
  const std::vector<long>& step_limiting_counts() const;
  double current_time() const;
  IntegratorStats stats() const;
  LinearSolverKind linear_solver() const { return solver_kind_; }
  /// The last message IDA reported (errors and warnings), empty if none.
  const std::string& last_message() const { return last_message_; }

  // Internal (C callbacks).
  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
  DaeSystem* system_;
  IntegratorOptions options_;
  LinearSolverKind solver_kind_{LinearSolverKind::kDense};
  std::string last_message_;
  bool initialized_{false};
  /// The cached polynomial (CacheStepPolynomial): φ_j's data, ψ_j and 1/ψ_j, j = 0..poly_order_.
  std::array<const double*, 6> poly_phi_{};
  std::array<double, 6> poly_psi_{}, poly_inverse_psi_{};
  std::vector<double> poly_power_;  // the power form's rows T_m, (k_used + 1) × N
  bool poly_power_form_{false};     // evaluated in the power form, else from φ_j
  int poly_order_{-1};
  double poly_tn_{0.0}, poly_t0_{0.0};
  /// Components [begin, end) of y(t), with ẏ(t) if kRates, in the cached form (written through
  /// `into` as EvaluateStepPolynomial documents).
  template <bool kRates>
  void EvaluateRange(double t, size_t begin, size_t end, const int* into, double* y,
                     double* yp) const;
};

}  // namespace flexrod::multibody
