// multibody/simulation_loop.cc — the run loop of Simulate: IDA's steps, the sample grid, the
// roots (element events and the crank index), stop times, re-initialisations, budgets and the
// failure report.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "common/error.h"
#include "common/scope_timer.h"
#include "multibody/ida_integrator.h"
#include "multibody/prescribed.h"
#include "multibody/simulate.h"
#include "multibody/simulate_internal.h"

namespace flexrod::multibody {
namespace {

using Clock = std::chrono::steady_clock;
constexpr long kDeadlineCheckSteps = 32;  // steps between reads of the wall clock

// Generic IDA advice plus what it usually means in a mechanism.
std::string HintForFlag(int flag) {
  std::string h = IdaFailureHint(flag);
  if (h.find("singular") != std::string::npos) {
    h += " — redundant constraints, a dead-centre configuration, or a coordinate without mass "
         "or constraint";
  } else if (h.find("residual") != std::string::npos) {
    h += " — an element reported a problem (e.g. penetration outside its valid range) or "
         "forces are not finite: check contact stiffness and element parameters";
  } else if (h.find("Newton") != std::string::npos || h.find("error-test") != std::string::npos) {
    h += "; check the contact stiffness, the friction regularisation speed and the element "
         "finite-difference scales";
  }
  return h;
}

/// Coordinates a restart's projection may move: all but the elastic ones (as the initial
/// conditions), so the correction is the rigid-body motion that closes the joints.
std::vector<int> RigidCoordinates(const Mechanism& model) {
  std::vector<int> out;
  std::vector<bool> elastic(model.num_coordinates(), false);
  for (const Body& b : model.bodies())
    for (int k = 0; k < b.num_modes; ++k) elastic[b.coordinate(kFirstMode + k)] = true;
  for (int i = 0; i < model.num_coordinates(); ++i)
    if (!elastic[i]) out.push_back(i);
  return out;
}

/// One integration from a consistent state to options.t_end. IDA integrates the kept unknowns
/// (size n, multibody/prescribed.h); everything else sees the full layout (size N).
class SimulationLoop {
 public:
  SimulationLoop(const Mechanism& model, RunData* data, const ConsistentState& state,
                 const SimulationOptions& options, const SimulationCallbacks& callbacks,
                 double velocity_tol_scale)
      : model_(model),
        data_(data),
        state_(state),
        options_(options),
        callbacks_(callbacks),
        N_(model.size()),
        np_(model.num_coordinates()),
        t_end_(options.t_end),
        t_fuzz_(1e-12 * std::max(1.0, std::abs(options.t_end))),
        dt_(1.0 / options.sample_rate),
        prescribed_(model, options.eliminate_prescribed),
        dae_(model, data, prescribed_, options.index_event, velocity_tol_scale,
             options.energy_tol_scale),
        ida_(&dae_, options.integrator),
        yr_(prescribed_.size()),
        ypr_(prescribed_.size()),
        ybuf_(state.y),
        ypbuf_(state.yp),
        yev_(N_),
        ypev_(N_),
        projected_(RigidCoordinates(model)),
        step_interval_(
            model, data,
            [this](double t, double* y, double* yp) {
              CacheStepPolynomial();
              ida_.EvaluateStepPolynomial(t, y, yp, prescribed_.kept_unknowns().data());
              prescribed_.ExpandPrescribed(t, y, yp);
            },
            [this](double t, ElementId e, double* y) {
              CacheStepPolynomial();
              EvaluateElementInputs(t, e, y);
            },
            &ybuf_, &ypbuf_) {
    status_.velocity_tol_scale = velocity_tol_scale;
    status_.linear_solver = ida_.linear_solver();
    element_inputs_.resize(model.elements().size());
    status_.unknowns = prescribed_.size();
  }

  SimulationStatus Run() {
    const double t0 = state_.t;
    data_->reference_energy = InitialEnergy(model_, data_, state_.y);
    t_now_ = t0;
    Initialize(t0, state_.y, state_.yp);
    stops_ = model_.Breakpoints(t0, t_end_);
    stops_.push_back(t_end_);
    ida_.SetStopTime(stops_[0]);
    grid_active_ = !options_.start_sampling_at_index;
    grid_start_ = options_.sample_start;
    if (grid_active_) {
      k_next_ = std::max(0L, static_cast<long>(std::ceil((t0 - grid_start_) / dt_ - 1e-9)));
    }
    roots_.assign(std::max(1, dae_.num_roots()), 0);
    EmitUpTo(t0, false);
    try {
      Loop();
      if (status_.outcome == SimulationOutcome::kCompleted) status_.t_reached = t_now_;
    } catch (const IntegratorFailure& e) {
      FillFailure(SimulationOutcome::kIntegratorFailure, e.what(), HintForFlag(e.flag()), e.time());
    } catch (const NumericalError& e) {
      FillFailure(SimulationOutcome::kIntegratorFailure, e.what(),
                  "a restart or an IDA set-up call failed: check the model near this time", t_now_);
    }
    status_.stats = ida_.stats();
    status_.output_seconds = output_seconds_;
    const std::vector<long>& limiting = ida_.step_limiting_counts();
    for (size_t i = 0; i < limiting.size(); ++i) {
      if (limiting[i] == 0) continue;
      const int full = prescribed_.kept_unknowns()[i];
      status_.step_limiting.emplace_back(model_.VariableName(full), limiting[i]);
    }
    std::stable_sort(status_.step_limiting.begin(), status_.step_limiting.end(),
                     [](const auto& a, const auto& b) { return a.second > b.second; });
    return status_;
  }

 private:
  void Initialize(double t, const Vec& y, const Vec& yp) {
    prescribed_.StartSegment(t);
    prescribed_.Reduce(y.data(), yr_.data());
    prescribed_.Reduce(yp.data(), ypr_.data());
    ida_.Initialize(t, yr_.data(), ypr_.data());
    step_polynomial_cached_ = false;
  }

  /// The last step's interpolating polynomial, built at most once per IDA return: the samples
  /// and the step-interval callbacks (the impact-peak search) of one step share it.
  void CacheStepPolynomial() {
    if (step_polynomial_cached_) return;
    ida_.CacheStepPolynomial(grid_active_ ? dt_ : 0.0);  // its form: how many samples it holds
    step_polynomial_cached_ = true;
  }

  /// What a force element reads (EvaluateElementInputs).
  struct ElementInputs {
    bool built{false};
    std::vector<std::pair<int, int>> runs;  // [begin, end) of reduced components
    std::vector<int> prescribed_bodies;     // its markers' bodies with prescribed coordinates
  };

  /// y(t) of the step's polynomial for the unknowns force element e reads (its markers' bodies'
  /// coordinates and velocities, its states), prescribed bodies from their motion:
  /// StepInterpolant::ElementAt.
  void EvaluateElementInputs(double t, ElementId e, double* y) {
    ElementInputs& in = element_inputs_[static_cast<size_t>(e.index)];
    if (!in.built) BuildElementInputs(e, &in);
    for (const auto& [begin, end] : in.runs) {
      ida_.EvaluateStepPolynomialValues(t, begin, end, y, prescribed_.kept_unknowns().data());
    }
    for (const int b : in.prescribed_bodies) {
      prescribed_.ExpandPrescribedBody(t, b, y, ypbuf_.data());
    }
  }

  /// Element e's unknowns as runs of consecutive reduced components, and the bodies among its
  /// markers' whose coordinates are prescribed (once per element, on first use).
  void BuildElementInputs(ElementId e, ElementInputs* in) const {
    const ElementSlot& slot = model_.element(e);
    const std::vector<int>& kept = prescribed_.kept_unknowns();
    auto reduced = [&kept](int i) {  // i's reduced index, −1 if prescribed
      const auto it = std::lower_bound(kept.begin(), kept.end(), i);
      return it != kept.end() && *it == i ? static_cast<int>(it - kept.begin()) : -1;
    };
    std::vector<int> components;
    for (const int mi : {slot.marker_i, slot.marker_j}) {
      const int b = model_.markers()[mi].body;
      if (b < 0 || std::find(in->prescribed_bodies.begin(), in->prescribed_bodies.end(), b) !=
                       in->prescribed_bodies.end())
        continue;
      const Body& body = model_.bodies()[b];
      bool prescribed = false;
      for (int c = body.coordinate_offset; c < body.coordinate_offset + body.num_coordinates();
           ++c) {
        for (const int i : {c, np_ + c}) {
          const int r = reduced(i);
          if (r < 0) {
            prescribed = true;
          } else {
            components.push_back(r);
          }
        }
      }
      if (prescribed) in->prescribed_bodies.push_back(b);
    }
    for (int k = 0; k < slot.num_states; ++k) {
      components.push_back(reduced(model_.z_offset() + slot.state_offset + k));
    }
    std::sort(components.begin(), components.end());
    components.erase(std::unique(components.begin(), components.end()), components.end());
    for (const int r : components) {
      if (!in->runs.empty() && in->runs.back().second == r) {
        ++in->runs.back().second;
      } else {
        in->runs.emplace_back(r, r + 1);
      }
    }
    in->built = true;
  }

  /// The integrator's current state in the full layout.
  void ExpandCurrent(double t, Vec* y, Vec* yp) {
    prescribed_.Expand(t, ida_.y(), ida_.yp(), y->data(), yp->data());
  }

  /// Offers the samples of the grid t_k = grid_start + k / rate up to t_ret: from the step's
  /// interpolating polynomial, or (before the first step) the initial state.
  void EmitUpTo(double t_ret, bool from_dense) {
    // The next grid sample's time, if it is due by t_ret.
    const auto due = [&](double* ts) {
      *ts = grid_start_ + static_cast<double>(k_next_) * dt_;
      return *ts <= t_ret + t_fuzz_ && *ts <= t_end_ + t_fuzz_;
    };
    double ts = 0.0;
    if (!grid_active_ || !due(&ts)) return;  // a step without a sample reads no clock
    const ScopeTimer timer(&output_seconds_);
    for (; due(&ts); ++k_next_) {
      if (from_dense) {
        CacheStepPolynomial();  // once per step, not per sample
        const double te = std::min(ts, t_ret);
        ida_.EvaluateStepPolynomial(te, ybuf_.data(), ypbuf_.data(),
                                    prescribed_.kept_unknowns().data());
        prescribed_.ExpandPrescribed(te, ybuf_.data(), ypbuf_.data());
        Emit(ts, ybuf_.data(), ypbuf_.data());
      } else {
        Emit(ts, state_.y.data(), state_.yp.data());
      }
    }
  }

  void Emit(double t, const double* y, const double* yp) {
    ++status_.num_samples;
    if (callbacks_.on_sample) callbacks_.on_sample(SampleView(model_, data_, t, y, yp));
  }

  /// The solution point at t_now in yev/ypev, for on_step (each outcome refreshes them).
  void ReportStep() {
    if (callbacks_.on_step)
      callbacks_.on_step(SampleView(model_, data_, t_now_, yev_.data(), ypev_.data()));
  }

  /// Re-initialises IDA at t from yev, projected onto the constraints first: IDA's state meets
  /// them only to its tolerance, and restarting from it unprojected can leave the first step no
  /// consistent start (IDA_ERR_FAIL at h ~ 1e-19 after a contact onset on the rigid rig).
  void Restart(double t) {
    ProjectOntoConstraints(model_, data_, t, projected_, &yev_, &ypev_);
    Initialize(t, yev_, ypev_);
    ida_.SetStopTime(stops_[stop_index_]);
  }

  /// The integrator's steps until t_end, a budget or a stop request.
  void Loop() {
    long steps = 0;
    int stalls = 0;  // consecutive kRootStall re-initialisations
    constexpr int kMaxRootStalls = 3;
    for (;;) {
      const double t_before = t_now_;
      const StepResult res = ida_.Step(t_end_);
      step_polynomial_cached_ = false;
      if (res.outcome != StepOutcome::kRootStall) {
        t_now_ = res.t;
        stalls = 0;
      }
      if (res.outcome == StepOutcome::kStep) ++steps;
      EmitUpTo(t_now_, true);
      if (res.outcome == StepOutcome::kStep) OnStep(t_before);
      if (res.outcome == StepOutcome::kRoot) {
        OnRoot();
      } else if (res.outcome == StepOutcome::kRootStall) {
        // y still holds the solution at the last return (IDA has not stepped since).
        if (++stalls > kMaxRootStalls) {
          throw IntegratorFailure(
              "IDA cannot continue past a root function that stays zero at t = " +
                  FormatValue(t_now_) + " s (" + std::to_string(kMaxRootStalls) +
                  " re-initialisations did not help)",
              -22, "IDA_ILL_INPUT", t_now_);
        }
        ExpandCurrent(t_now_, &yev_, &ypev_);
        Restart(t_now_);
        ++status_.root_stall_restarts;
        continue;
      } else if (res.outcome == StepOutcome::kStopTime) {
        if (OnStopTime()) break;
      }
      if (t_end_ - t_now_ <= t_fuzz_ || BudgetExhausted(steps)) break;
    }
  }

  /// An accepted step from t_before to t_now: its interval, then its end point.
  void OnStep(double t_before) {
    if (callbacks_.on_step_interval) {
      step_interval_.SetInterval(t_before, t_now_);
      callbacks_.on_step_interval(step_interval_);
    }
    if (callbacks_.on_step) {
      ExpandCurrent(t_now_, &yev_, &ypev_);
      ReportStep();
    }
  }

  /// A located root: the elements' events (restart if one asks), the crank index (which may
  /// start the sample grid).
  void OnRoot() {
    int* roots = roots_.data();
    ida_.RootInfo(roots);
    ExpandCurrent(t_now_, &yev_, &ypev_);
    const bool must_restart = ApplyElementRoots(model_, data_, t_now_, yev_.data(), roots);
    const int index_root = dae_.index_root();
    if (index_root >= 0 && roots[index_root] != 0) OnIndex();
    if (must_restart && t_end_ - t_now_ > t_fuzz_) Restart(t_now_);
    ReportStep();
  }

  void OnIndex() {
    const int ith = model_.coordinate(options_.index_event->body, kTheta);
    IndexCrossing c;
    c.t = t_now_;
    c.revolution =
        std::lround((yev_(ith) - options_.index_event->angle) / (2.0 * std::numbers::pi));
    c.speed = yev_(np_ + ith);
    status_.index_crossings.push_back(c);
    if (!grid_active_ && t_now_ >= options_.sample_start - t_fuzz_) {
      grid_active_ = true;
      grid_start_ = t_now_;
      k_next_ = 0;
      EmitUpTo(t_now_, true);
    }
    if (callbacks_.on_index) {
      callbacks_.on_index(c, SampleView(model_, data_, t_now_, yev_.data(), ypev_.data()));
    }
  }

  /// A stop time: t_end (true: done) or a speed-profile knot, where the prescribed
  /// acceleration jumps (restart).
  bool OnStopTime() {
    ExpandCurrent(t_now_, &yev_, &ypev_);
    if (stop_index_ + 1 >= stops_.size() || t_end_ - t_now_ <= t_fuzz_) {  // t_end reached
      ReportStep();
      return true;
    }
    ++stop_index_;
    Restart(t_now_);
    ReportStep();
    return false;
  }

  /// The step budget, the wall-clock deadline or a stop request: fills the status, true.
  bool BudgetExhausted(long steps) {
    if (options_.max_steps > 0 && steps >= options_.max_steps) {
      FillFailure(SimulationOutcome::kStepLimit,
                  "step budget of " + std::to_string(options_.max_steps) + " steps exhausted",
                  "increase the step budget (sim.max_steps), loosen tolerances or check for "
                  "chattering events",
                  t_now_);
      return true;
    }
    // The clock is read on the first step and every kDeadlineCheckSteps after it (with the
    // output timer's two reads in every step, the clock was 1 % of the exudyn-match clearance
    // case, 423 000 steps).
    if (options_.deadline && steps % kDeadlineCheckSteps == 1 &&
        Clock::now() > *options_.deadline) {
      FillFailure(SimulationOutcome::kWallTimeLimit, "wall-clock budget exhausted",
                  "increase the wall-clock budget (sim.max_wall_time), loosen tolerances or "
                  "shorten the simulated time",
                  t_now_);
      return true;
    }
    if (options_.stop != nullptr && options_.stop->load(std::memory_order_relaxed)) {
      FillFailure(SimulationOutcome::kInterrupted, "interrupted by the caller",
                  "run it again; nothing is wrong with the input", t_now_);
      return true;
    }
    return false;
  }

  /// The outcome, message and hint, with the last state IDA returned: every body's
  /// coordinates and rates by name, the largest residual and weighted local error.
  void FillFailure(SimulationOutcome outcome, const std::string& message, const std::string& hint,
                   double t_fail) {
    status_.outcome = outcome;
    status_.message = message;
    status_.hint = hint;
    status_.t_reached = t_fail;
    Vec y(N_), yp(N_);
    ExpandCurrent(t_now_, &y, &yp);
    status_.norm_coordinates = y.head(np_).norm();
    status_.norm_velocities = y.segment(np_, np_).norm();
    status_.norm_multipliers = y.segment(model_.lambda_offset(), model_.num_constraints()).norm();
    status_.failure_state.clear();
    for (int offset : {0, np_}) {
      for (const Body& b : model_.bodies()) {
        for (int c : {kX, kY, kTheta}) {
          const int i = offset + b.coordinate(c);
          status_.failure_state.emplace_back(model_.VariableName(i), y(i));
        }
      }
    }
    Vec r(N_);
    CalcResidual(model_, data_, t_now_, y.data(), yp.data(), r.data());
    status_.worst_residual_index = WorstIndex(r);
    if (status_.worst_residual_index >= 0) {
      status_.worst_residual = r(status_.worst_residual_index);
      status_.worst_residual_variable = model_.VariableName(status_.worst_residual_index);
    }
    ida_.WorstLocalError(&status_.worst_error_index, &status_.worst_weighted_error);
    if (status_.worst_error_index >= 0) {
      status_.worst_error_index = prescribed_.kept_unknowns()[status_.worst_error_index];
      status_.worst_error_variable = model_.VariableName(status_.worst_error_index);
    }
  }

  const Mechanism& model_;
  RunData* data_;
  const ConsistentState& state_;
  const SimulationOptions& options_;
  const SimulationCallbacks& callbacks_;
  const int N_, np_;
  const double t_end_, t_fuzz_, dt_;  // [s]
  PrescribedMotion prescribed_;
  MechanismDae dae_;
  IdaIntegrator ida_;
  SimulationStatus status_;
  Vec yr_, ypr_;                               // reduced state (IDA's layout)
  Vec ybuf_, ypbuf_;                           // full dense-output buffers
  std::vector<ElementInputs> element_inputs_;  // by element index
  Vec yev_, ypev_;                             // full event/restart state
  const std::vector<int> projected_;
  std::vector<double> stops_;
  size_t stop_index_{0};
  bool grid_active_{false};
  double grid_start_{0.0};  // [s]
  long k_next_{0};          // next sample index on the grid
  double output_seconds_{0.0};
  double t_now_{0.0};  // time of the integrator's returned state (ida.y())
  std::vector<int> roots_;
  // The interval view of each accepted step (on_step_interval), built once: its polynomial is
  // cached on the first evaluation inside the step.
  bool step_polynomial_cached_{false};
  StepInterpolant step_interval_;
};

}  // namespace

SimulationStatus Simulate(const Mechanism& model, RunData* data, const ConsistentState& state,
                          const SimulationOptions& options, const SimulationCallbacks& callbacks) {
  const auto wall0 = Clock::now();
  options.Validate(model);
  FLEXROD_ASSERT(data->model == &model);
  Require(state.y.size() == model.size() && state.yp.size() == model.size(), "simulation.state",
          state.y.size(), "must have model.size() entries");
  Require(options.t_end > state.t, "simulation.t_end", options.t_end,
          "must be > the start time of the state");
  const double velocity_tol_scale =
      options.velocity_tol_scale > 0.0 ? options.velocity_tol_scale : AutoVelocityTolScale(model);
  data->time_elements = options.time_elements;
  for (ElementScratch& es : data->elements) es.seconds = 0.0;
  SimulationLoop loop(model, data, state, options, callbacks, velocity_tol_scale);
  SimulationStatus status = loop.Run();
  if (options.time_elements) {
    for (const ElementScratch& es : data->elements) status.element_seconds.push_back(es.seconds);
  }
  status.wall_seconds = std::chrono::duration<double>(Clock::now() - wall0).count();
  return status;
}

}  // namespace flexrod::multibody
