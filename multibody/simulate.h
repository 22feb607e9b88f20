// multibody/simulate.h — running a mechanism: consistent initial conditions (positions by
// minimum-norm Newton, velocities by minimum-norm projection, accelerations and multipliers
// from the augmented system, optional static equilibrium of the elastic coordinates), the
// IDA adapter of the mechanism DAE, and the run loop with fixed-rate output interpolated
// from IDA's dense output, index-angle events, element events (contact onset) with restarts,
// and a failure status that keeps everything produced so far. What does not live here: the
// equations (dae.h), the IDA calls (ida_integrator.h), the queries (outputs.h).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <atomic>
#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/eigen.h"
#include "multibody/dae.h"
#include "multibody/ida_integrator.h"
#include "multibody/mechanism.h"
#include "multibody/outputs.h"
#include "multibody/prescribed.h"
#include "multibody/run_data.h"

namespace flexrod::multibody {

// ---- initial conditions -------------------------------------------------------------------------
enum class ElasticInitialState {
  kUndeformed,         ///< q = guess (normally 0), q̇ = guess
  kStaticEquilibrium,  ///< q such that the elastic coordinates are in quasi-static equilibrium
                       ///< (q̈ = 0, q̇ = 0) under inertial/external loads at t0
};

struct InitialConditionSpec {
  Vec coordinates;  ///< guess of p (np); empty = zeros. Elastic entries are kept (or relaxed).
  Vec velocities;   ///< guess of v (np); empty = zeros.
  /// Coordinates held at their guess by the position Newton (elastic coordinates always are).
  std::vector<int> fixed_coordinates;
  /// Velocities held at their guess by the velocity projection (elastic velocities always are).
  std::vector<int> fixed_velocities;
  ElasticInitialState elastic{ElasticInitialState::kUndeformed};
  double position_tolerance{1e-12};     ///< max |g| accepted [m or rad], > 0
  int max_newton_iterations{50};        ///< >= 1
  int max_equilibrium_iterations{100};  ///< static-equilibrium fixed point, >= 1
  void Validate(const Mechanism& model) const;
};

/// A consistent (t, y, ẏ): g = 0, G v + g_t = 0, M v̇ + Gᵀλ = Q, μ = 0, ṗ = v, ż = f.
struct ConsistentState {
  double t{0.0};
  Vec y, yp;
};

/// Throws NumericalError when the Newton does not converge or the constraints are redundant
/// (rank-deficient G, singular augmented matrix), InputError for bad specs.
ConsistentState ComputeConsistentState(const Mechanism& model, RunData* data, double t0,
                                       const InitialConditionSpec& spec);

/// Recomputes v̇, λ (μ = 0), ṗ = v and ż at fixed (p, v, z): used after events and restarts.
void ComputeConsistentDerivatives(const Mechanism& model, RunData* data, double t, Vec* y, Vec* yp);

/// The elements' events at a located root, as the run loop handles every IDA root: the
/// kinematics at the full state y (UpdateKinematics), then each element whose root function k
/// crossed (roots[root_offset + k] = ±1, IDA's directions) updates its memory and states
/// (ForceElement::OnRoot). True if one of them asks for a re-initialisation.
bool ApplyElementRoots(const Mechanism& model, RunData* data, double t, double* y,
                       const int* roots);

/// Convenience for building guesses: writes a body's frame pose / velocity into p / v.
void SetBodyPose(const Mechanism& model, BodyId body, const Vec2& origin, double angle, Vec* p);
void SetBodyVelocity(const Mechanism& model, BodyId body, const Vec2& velocity,
                     double angular_velocity, Vec* v);

// ---- the DAE adapter ----------------------------------------------------------------------------
struct IndexEventSpec {
  BodyId body;        ///< whose frame angle θ is watched
  double angle{0.0};  ///< θ_index [rad]; events at θ = θ_index + 2πk
};

/// The mechanism DAE seen by IdaIntegrator, on the unknowns `prescribed` keeps (prescribed.h):
/// each call expands them to the full layout, evaluates dae.h there and gathers the kept rows
/// (and columns). Roots: the element roots, then (optionally) the index root
/// sin((θ − θ_index)/2), which changes sign exactly at θ = θ_index + 2πk.
class MechanismDae final : public DaeSystem {
 public:
  MechanismDae(const Mechanism& model, RunData* data, const PrescribedMotion& prescribed,
               std::optional<IndexEventSpec> index, double velocity_tol_scale = 1.0,
               double energy_tol_scale = 1.0);
  int size() const override { return prescribed_.size(); }
  int num_roots() const override;
  void DifferentialMask(double* id) const override;
  /// The multipliers λ, μ (index 2); not the energy quadratures.
  void StepScaledWeightMask(double* mask) const override;
  void AbsoluteToleranceScales(double* scales) const override;
  /// Coordinates that move a marker of an element with a resolved length L
  /// (ForceElement::ResolvedLength): L for the frame position, L/|ū₀| for the frame angle.
  void RelativeToleranceCaps(double* caps) const override;
  int Residual(double t, const double* y, const double* yp, double* r) override;
  int Jacobian(double t, double cj, const double* y, const double* yp, double* jac) override;
  /// In one evaluation: dF/dẏ is the identities of the position and state rows and the
  /// bodies' mass matrices (AddJacobian).
  int JacobianAndDerivativePart(double t, double cj, const double* y, const double* yp, double* jac,
                                double* dfdyp) override;
  SparsityPattern JacobianPattern() const override;
  int Roots(double t, const double* y, const double* yp, double* g) override;
  int index_root() const;  ///< position of the index root, −1 if none

 private:
  void Expand(double t, const double* y, const double* yp);
  const Mechanism& model_;
  RunData* data_;
  const PrescribedMotion& prescribed_;
  std::optional<IndexEventSpec> index_;
  double velocity_tol_scale_, energy_tol_scale_;
  Vec y_full_, yp_full_, r_full_;  ///< full-layout scratch
  /// dfdyp null: Jacobian; else JacobianAndDerivativePart.
  int AddJacobians(double t, double cj, const double* y, const double* yp, double* jac,
                   double* dfdyp);
  Mat jac_full_, dfdyp_full_;     // zero between Jacobians (MoveReducedMatrix)
  SparsityPattern full_pattern_;  // the full Jacobian's
  long jacobians_{0};             // Jacobians evaluated (the pattern check's interval)
};

// ---- run loop -----------------------------------------------------------------------------------
/// Velocity tolerance scale [1/s] for models where joints or force elements act on elastic
/// coordinates. A position error δp implies a velocity error ω·δp in a mode of angular
/// frequency ω. When stiff elastic coordinates enter joint constraints, tolerance-level
/// position errors of the rigid-body coordinates excite them, and IDA's (unfiltered) error
/// estimate of their velocities pins the step near 1/|λ_max| with an error-test failure on
/// nearly every step (a joint on the rod's frame node: 480 steps; the same joint on its
/// elastic tip: 93 743 steps). Measured on the flexible slider-crank (steel Craig–Bampton rod,
/// 8 modes, band damping, 4 s): scale 1e2 trapped at every rel_tol in 1e-5..1e-8, 1e3 at
/// 1e-5 and 1e-8, 1e4 and 1e5 never (1000–9000 steps). Accuracy cost against a 1e-10
/// reference (0.5 s): slider acceleration 1e-3 (1e3) / 7e-3 (1e4) at rel_tol 1e-7, 2e-4 /
/// 3e-3 at 1e-8 — tighten rel_tol for accelerations. The extreme 10⁴-stiffer rod traps at 1e4
/// and runs at 1e3: the trap depends on where the accuracy-limited step falls relative to the
/// stiff eigenvalues; SimulationStatus::Summary() flags it. IdaIntegrator's step-growth guard
/// (multibody/ida_integrator.cc, kGrowthWindow) limits the step growth while most steps fail,
/// which frees the step control on the cases measured when it was added (commit ca42b32).
inline constexpr double kElasticJointVelocityTolScale = 1e4;
/// 1 if every joint and force-element marker moves only with frame coordinates (rigid bodies,
/// frame points of flexible bodies), kElasticJointVelocityTolScale otherwise.
double AutoVelocityTolScale(const Mechanism& model);

struct SimulationOptions {
  double t_start{0.0};       ///< [s]
  double t_end{1.0};         ///< [s], > t_start
  double sample_rate{1e5};   ///< output rate [Hz], > 0
  double sample_start{0.0};  ///< first sample time [s] (samples on t = sample_start + k/rate)
  /// If true, the sample grid starts at the first index crossing at or after sample_start
  /// (rig-style triggered capture; needs index_event).
  bool start_sampling_at_index{false};
  std::optional<IndexEventSpec> index_event;
  IntegratorOptions integrator;
  long max_steps{0};  ///< integrator steps allowed for the run; 0 = unlimited
  /// Wall-clock time by which the run must end (checked after every step); none = unlimited.
  /// A deadline, not a duration, so that a run of several integrations shares one budget.
  std::optional<std::chrono::steady_clock::time_point> deadline;
  /// Absolute tolerance of the velocities v = abs_tol · velocity_tol_scale [1/s], >= 0;
  /// 0 (default) = AutoVelocityTolScale(model). See kElasticJointVelocityTolScale.
  double velocity_tol_scale{0.0};
  double energy_tol_scale{1.0};  ///< abs tolerance of the energy quadratures = abs_tol · this, > 0
  /// Integrate without the coordinates that ground-side constraints prescribe (prescribed.h);
  /// false integrates the full DAE (the same solution; for checks).
  bool eliminate_prescribed{true};
  /// Time each force element's evaluations in residuals and its Jacobian block
  /// (SimulationStatus::element_seconds); off by default (two clock reads per element per call).
  bool time_elements{false};
  /// Polled after every integrator step: once it reads true, the run stops with outcome
  /// kInterrupted, keeping what it produced (a caller's Ctrl-C). nullptr: never stops.
  const std::atomic<bool>* stop{nullptr};
  void Validate(const Mechanism& model) const;
};

struct IndexCrossing {
  double t{0.0};       ///< [s]
  long revolution{0};  ///< k in θ = θ_index + 2πk
  double speed{0.0};   ///< θ̇ at the crossing [rad/s]
};

/// One output sample: the state, its derivative, and lazily computed queries.
class SampleView {
 public:
  SampleView(const Mechanism& model, RunData* data, double t, const double* y, const double* yp);
  double t() const { return t_; }
  const Mechanism& model() const { return model_; }
  RunData& data() const { return *data_; }
  const double* y() const { return y_; }
  const double* yp() const { return yp_; }
  double coordinate(int i) const { return y_[i]; }                                ///< p_i
  double velocity(int i) const { return y_[model_.num_coordinates() + i]; }       ///< v_i
  double acceleration(int i) const { return yp_[model_.num_coordinates() + i]; }  ///< v̇_i
  /// Marker m's kinematics. Asked before any query that needs the whole update, it refreshes
  /// marker m alone: its body's orientation and the marker, not every body and marker.
  const MarkerKinematics& Marker(MarkerId m) const;
  Vec2 MarkerAcceleration(MarkerId m) const;
  JointReaction Reaction(JointId j) const;
  DriverState Driver(DriverId d) const;
  ElementReport Element(ElementId e) const;
  EnergyReport Energies() const;
  double ConstraintViolation() const;
  /// An element query that has evaluated element e at this sample (CalcClearanceResponse)
  /// leaves its potential energy [J] here, so that Energies() does not evaluate it again.
  void NotePotentialEnergy(ElementId e, double energy) const { known_ = {e.index, energy}; }

 private:
  void Ready() const;
  const Mechanism& model_;
  RunData* data_;
  double t_;
  const double* y_;
  const double* yp_;
  mutable bool ready_{false};
  mutable KnownPotential known_;
};

/// The integrator's last accepted step as a function of time: the solution anywhere in
/// [t_begin(), t_end()] from the step's interpolating polynomial (the one the samples come
/// from), for callers that locate an extremum inside a step (the impact log's peaks).
class StepInterpolant {
 public:
  /// Writes y(t), ẏ(t) (full layout) for t in the step.
  using Evaluate = std::function<void(double t, double* y, double* yp)>;
  /// Writes y(t) (full layout) only for the unknowns force element e reads: its markers'
  /// bodies' coordinates and velocities, its states.
  using EvaluateElement = std::function<void(double t, ElementId e, double* y)>;
  StepInterpolant(const Mechanism& model, RunData* data, Evaluate evaluate,
                  EvaluateElement evaluate_element, Vec* y, Vec* yp)
      : model_(model),
        data_(data),
        evaluate_(std::move(evaluate)),
        evaluate_element_(std::move(evaluate_element)),
        y_(y),
        yp_(yp) {}
  /// The step [t_begin, t_end] [s] that `evaluate` now interpolates.
  void SetInterval(double t_begin, double t_end) {
    t_begin_ = t_begin;
    t_end_ = t_end;
  }
  double t_begin() const { return t_begin_; }  ///< [s]
  double t_end() const { return t_end_; }      ///< [s]
  /// The solution at t, clamped to the step; valid until the next call of At or ElementAt.
  SampleView At(double t) const;
  /// The solution at t, clamped to the step, for force element e's own queries only
  /// (CalcClearanceResponse): of y, only what e reads is evaluated (its markers' bodies'
  /// coordinates and velocities, its states), the same numbers At gives them; ẏ and the other
  /// unknowns are stale, so the view serves no other query. Valid until the next At or ElementAt.
  SampleView ElementAt(double t, ElementId e) const;

 private:
  const Mechanism& model_;
  RunData* data_;
  Evaluate evaluate_;
  EvaluateElement evaluate_element_;
  double t_begin_{0.0}, t_end_{0.0};
  Vec* y_;
  Vec* yp_;
};

struct SimulationCallbacks {
  std::function<void(const SampleView&)> on_sample;
  /// Each accepted step as a whole, before on_step reports its end point (the samples inside
  /// it have been offered).
  std::function<void(const StepInterpolant&)> on_step_interval;
  /// Every solution point the integrator returns: each accepted step's end, each located root
  /// (after the elements' OnRoot updates and the restart) and each stop time. In time order
  /// with the samples; a sample at the same time comes first.
  std::function<void(const SampleView&)> on_step;
  std::function<void(const IndexCrossing&, const SampleView&)> on_index;
};

enum class SimulationOutcome {
  kCompleted,
  kIntegratorFailure,        ///< IDA gave up (status has time, state, hint)
  kStepLimit,                ///< options.max_steps reached
  kWallTimeLimit,            ///< options.deadline passed
  kInitialConditionFailure,  ///< no consistent initial state
  kInterrupted,              ///< SimulationOptions::stop was set (not a numerical failure)
};
const char* ToString(SimulationOutcome outcome);

struct SimulationStatus {
  SimulationOutcome outcome{SimulationOutcome::kCompleted};
  double t_reached{0.0};         ///< last time the integrator reached [s]
  std::string message;           ///< what went wrong (IDA flag and message)
  std::string hint;              ///< what to try
  double norm_coordinates{0.0};  ///< |p|₂ of the last state IDA returned
  double norm_velocities{0.0};   ///< |v|₂
  double norm_multipliers{0.0};  ///< |λ|₂
  int worst_residual_index{-1};  ///< unknown with the largest |F_i| at the last returned state
  std::string worst_residual_variable;
  double worst_residual{0.0};
  int worst_error_index{-1};  ///< unknown with the largest weighted local error estimate
  std::string worst_error_variable;
  double worst_weighted_error{0.0};
  /// On failure: every body's rigid coordinates and velocities (x, y, θ) at the last state IDA
  /// returned, by variable name ("p[crank.theta]" [m or rad], "v[crank.theta]" [m/s or rad/s]).
  std::vector<std::pair<std::string, double>> failure_state;
  /// IntegratorOptions::count_step_limiting: the unknowns that had the largest weighted local
  /// error estimate after a step ("v[rod.q2]"), each with the number of such steps, most steps
  /// first (the counts sum to the steps taken); empty otherwise.
  std::vector<std::pair<std::string, long>> step_limiting;
  long num_samples{0};
  long root_stall_restarts{0};  ///< re-initialisations past a root function stuck at zero
  int unknowns{0};              ///< unknowns IDA integrated (model.size() less the prescribed)
  std::vector<IndexCrossing> index_crossings;
  IntegratorStats stats;
  LinearSolverKind linear_solver{LinearSolverKind::kDense};
  double velocity_tol_scale{1.0};  ///< the velocity tolerance scale used [1/s]
  double wall_seconds{0.0};        ///< whole run [s]
  double output_seconds{0.0};      ///< dense output + observer callbacks [s]
  /// SimulationOptions::time_elements: per force element (model order), the wall time of its
  /// evaluations in residuals and of its Jacobian block [s]; empty otherwise.
  std::vector<double> element_seconds;
  bool ok() const { return outcome == SimulationOutcome::kCompleted; }
  std::string Summary() const;
};

/// At least this share of a run's steps at BDF order 1 (IntegratorStats::steps_by_order)
/// means IDA's step control is caught there: it starts every (re-)initialisation at order 1
/// and raises the order only after steps without a failure. Runs at the default tolerances
/// take a few percent of their steps there (the first ones after each contact onset); the
/// exudyn-match slider-crank with the ideal joint at rel_tol 1e-5 about half, and twice the
/// steps of the defaults (RunRobustness.AStepControlHeldAtOrderOneIsWarnedAbout).
inline constexpr double kCaughtOrderOneShare = 0.2;
/// What a run whose step control stiff elastic coordinates caught should be told, or "" : most
/// steps failed the error test, or at least kCaughtOrderOneShare of them were taken at order 1
/// (runs of at least 1 000 steps).
std::string CaughtStepControlNote(const IntegratorStats& stats);

/// Runs from a consistent state (state.t is the start time; options.t_start is ignored).
SimulationStatus Simulate(const Mechanism& model, RunData* data, const ConsistentState& state,
                          const SimulationOptions& options, const SimulationCallbacks& callbacks);
/// Computes the consistent state at options.t_start first.
SimulationStatus Simulate(const Mechanism& model, RunData* data, const InitialConditionSpec& ic,
                          const SimulationOptions& options, const SimulationCallbacks& callbacks);

}  // namespace flexrod::multibody
