// SPDX-License-Identifier: GPL-3.0-or-later
#include "run/run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <future>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>
#include <thread>
#include <utility>

#include "common/error.h"
#include "common/files.h"
#include "common/units.h"
#include "input/output_selection.h"
#include "mechanisms/exact_rod_view.h"
#include "mechanisms/mechanism_recipe.h"
#include "run/run_setup.h"
#include "run/vtk.h"
#include "signals/signals.h"

namespace flexrod {
namespace {

using multibody::SampleView;
constexpr double kTwoPi = 2.0 * std::numbers::pi;

}  // namespace

namespace {

/// Steps per BDF order: {"1": n₁, …, "5": n₅}.
nlohmann::json StepsByOrderJson(const multibody::IntegratorStats& s) {
  nlohmann::json j = nlohmann::json::object();
  for (int k = 1; k <= 5; ++k) j[std::to_string(k)] = s.steps_by_order[static_cast<size_t>(k)];
  return j;
}

/// The integrator's status and counters; with `profiled` (RunOutputOptions::profile) also the
/// wall time of its residuals, Jacobians and linear solves, and the unknowns that set the step
/// (SimulationStatus::step_limiting, most steps first).
nlohmann::json StatusJson(const multibody::SimulationStatus& st, bool profiled) {
  nlohmann::json j = {{"outcome", multibody::ToString(st.outcome)},
                      {"t_reached [s]", st.t_reached},
                      {"message", st.message},
                      {"hint", st.hint},
                      {"steps", st.stats.steps},
                      {"residual_evaluations", st.stats.residual_evaluations},
                      {"jacobian_evaluations", st.stats.jacobian_evaluations},
                      {"matrix_setups", st.stats.matrix_setups},
                      {"nonlinear_iterations", st.stats.nonlinear_iterations},
                      {"nonlinear_convergence_failures", st.stats.nonlinear_convergence_failures},
                      {"error_test_failures", st.stats.error_test_failures},
                      {"steps_by_order", StepsByOrderJson(st.stats)},
                      {"roots_found", st.stats.roots_found},
                      {"root_stall_restarts", st.root_stall_restarts},
                      {"linear_solver", multibody::ToString(st.linear_solver)},
                      {"unknowns", st.unknowns},
                      {"wall_time [s]", st.wall_seconds},
                      {"output_time [s]", st.output_seconds}};
  if (!st.ok()) {
    nlohmann::json state = nlohmann::json::object();  // [m, rad; m/s, rad/s] by coordinate
    for (const auto& [name, value] : st.failure_state) state[name] = value;
    j["state_at_failure [m, rad, m/s, rad/s]"] = state;
  }
  if (profiled) {
    j["residual_time [s]"] = st.stats.residual_seconds;
    j["jacobian_time [s]"] = st.stats.jacobian_seconds;
    j["linear_solve_time [s]"] = st.stats.linear_solve_seconds;
    nlohmann::json limiting = nlohmann::json::array();
    for (const auto& [unknown, steps] : st.step_limiting) {
      limiting.push_back({{"unknown", unknown}, {"steps", steps}});
    }
    j["step_limiting_unknowns"] = limiting;
  }
  return j;
}

/// The channels whose samples the run's own summary reads (the per-revolution statistics and
/// the load amplification, the impacts' revolutions, the mean crank speed): a run keeps them
/// whatever RunOutputOptions::keep_channel says.
constexpr const char* kSummaryChannels[] = {"crank_angle", "slider_acceleration", "bearing_force"};

/// A channel's peaks, RMS and per-revolution peak statistics as the summary writes them.
nlohmann::json SignalSummaryJson(const study::SignalSummary& a, const std::string& unit) {
  return {{"unit", unit},
          {"peak_positive", a.peak_positive},
          {"peak_negative", a.peak_negative},
          {"rms", a.rms},
          {"revolutions", a.positive.num_revolutions},
          {"per_revolution_positive",
           {{"median", a.positive.median}, {"p95", a.positive.p95}, {"max", a.positive.max}}},
          {"per_revolution_negative",
           {{"median", a.negative.median}, {"p95", a.negative.p95}, {"max", a.negative.max}}},
          {"per_revolution_abs",
           {{"median", a.magnitude.median}, {"p95", a.magnitude.p95}, {"max", a.magnitude.max}}}};
}

/// The rod's part of the summary (flexible and exact rods): peak gauge stress, safety factor,
/// frequencies; `warning`: the mesh-precision warning, or empty.
nlohmann::json RodSummaryJson(const Recorder& rec, const MechanismModel& mm, std::string* warning) {
  nlohmann::json rod;
  double peak_stress = 0.0;
  for (size_t c = 0; c < rec.names().size(); ++c) {
    if (rec.names()[c].rfind("stress_", 0) == 0)
      peak_stress = std::max(peak_stress, rec.stats()[c].peak_abs());
  }
  const double yield = (mm.rod ? mm.rod->rod : mm.exact->rod).material.yield_strength;
  rod = {{"model", mm.rod ? "reduced" : "exact"},
         {"peak_gauge_stress [Pa]", peak_stress},
         {"yield_strength [Pa]", yield},
         {"safety_factor",
          peak_stress > 0.0 ? nlohmann::json(yield / peak_stress) : nlohmann::json(nullptr)}};
  if (mm.mechanism_frequencies_hz.size() > 0) {
    // The rod's modes in the assembled mechanism (crank held) and the damping ratios they get.
    const Vec& f = mm.mechanism_frequencies_hz;
    const Vec& z = mm.mechanism_damping_ratios;
    rod["mechanism_frequencies [Hz]"] = std::vector<double>(f.data(), f.data() + f.size());
    rod["mechanism_damping_ratios"] = std::vector<double>(z.data(), z.data() + z.size());
  }
  if (mm.rod) {
    rod["frequencies [Hz]"] =
        std::vector<double>(mm.rod->frequencies_hz.data(),
                            mm.rod->frequencies_hz.data() + mm.rod->frequencies_hz.size());
    *warning = fem::MeshPrecisionWarning(mm.rod->rod, mm.rod->reduction.method);
  }
  return rod;
}

/// The run's summary from its record, the recorder's running statistics of every channel (kept
/// in the record or not: Recorder::KeepOnly) and its slider acceleration statistics
/// (slider-cranks).
nlohmann::json Summarise(const RunResult& run, const Recorder& rec, const Config& cfg,
                         const MechanismModel& mm) {
  const study::TimeSeries& ts = run.channels;
  nlohmann::json s;
  if (ts.num_samples() == 0) return s;
  const std::vector<std::string>& names = rec.names();
  const std::vector<ChannelStats>& stats = rec.stats();
  FLEXROD_ASSERT(stats.size() == names.size() && rec.size() == ts.num_samples());
  auto stat = [&](std::string_view name) -> const ChannelStats& {
    const auto it = std::find(names.begin(), names.end(), name);
    FLEXROD_ASSERT(it != names.end());
    return stats[static_cast<size_t>(it - names.begin())];
  };
  for (size_t c = 0; c < stats.size(); ++c) {
    s["channels"][names[c]] = {
        {"unit", rec.units()[c]},
        {"peak_abs", stats[c].peak_abs()},
        {"rms", std::sqrt(stats[c].sum_squares / static_cast<double>(ts.num_samples()))}};
  }
  if (mm.recipe->turns_a_crank() && ts.num_samples() > 2) {
    // Crank speed over the capture: the mean from the angle advanced (exact for any sampling),
    // the extremes from the samples. A motor drive droops and fluctuates; the others hold it.
    const auto th = ts.values("crank_angle");
    const double duration = static_cast<double>(ts.num_samples() - 1) / ts.sample_rate();
    s["crank_speed"] = {{"mean [rad/s]", (th.back() - th.front()) / duration},
                        {"min [rad/s]", stat("crank_speed").min},
                        {"max [rad/s]", stat("crank_speed").max},
                        {"set [rad/s]", mm.drive.type == DriveOptions::Type::kProfile
                                            ? nlohmann::json(nullptr)
                                            : nlohmann::json(mm.drive.speed)}};
    if (run.slider_acceleration)
      s["slider_acceleration"] = SignalSummaryJson(*run.slider_acceleration, "m/s^2");
  }
  if (mm.rod || mm.exact) {
    std::string warning;
    s["rod"] = RodSummaryJson(rec, mm, &warning);
    if (!warning.empty()) s["warnings"].push_back(warning);
    if (!mm.damping_warning.empty()) s["warnings"].push_back(mm.damping_warning);
  }
  if (mm.clearance.index >= 0) {
    // Loaded contacts penetrate by micrometres; a tenth of the clearance means the law is far
    // too soft for the load, or the pin went through the bush.
    const double c = cfg.Quantity("joint.clearance");
    const double deepest = std::max(0.0, stat("penetration").max);
    if (deepest > 0.1 * c) {
      s["warnings"].push_back("the pin penetrated the bush by " + FormatValue(deepest) + " m, " +
                              std::to_string(std::lround(100.0 * deepest / c)) +
                              " % of joint.clearance: the contact law is too soft for the load");
    }
  }
  const double worst = stat("energy_balance_error").peak_abs(),
               scale = stat("energy_kinetic").peak_abs();
  if (worst > 1e-2 * scale) {
    // At the run default tolerances every normal and friction law closes the balance below 1e-3
    // of the peak kinetic energy on both rigs (tests/run/law_matrix_slowtest.cc; the standard
    // linear solid, which loses its wall's energy at onsets, below 1e-2; the presets' full runs:
    // 4e-5 to 9e-5).
    s["warnings"].push_back("the energy balance error is " + FormatValue(worst) +
                            " J, more than 1 % of the peak "
                            "kinetic energy: the run is not converged; tighten sim.rel_tol");
  }
  s["energy"] = {{"max_balance_error [J]", worst},
                 {"max_kinetic [J]", scale},
                 {"relative_balance_error", scale > 0 ? worst / scale : 0.0}};
  s["max_constraint_violation [m]"] = std::max(0.0, stat("constraint_violation").max);
  return s;
}

}  // namespace

namespace {

/// The integrator's options of a run of `mm` and its initial conditions `ic`: tolerances and
/// limits from sim.*, the capture window from the recipe, the wall-clock deadline counted from
/// `wall0`.
multibody::SimulationOptions RunOptions(const SimOptions& sim, const MechanismModel& mm,
                                        std::chrono::steady_clock::time_point wall0, bool profile,
                                        const std::atomic<bool>* stop,
                                        multibody::InitialConditionSpec* ic) {
  const multibody::Mechanism& m = mm.mechanism;
  multibody::SimulationOptions opt = IntegratorOptions(sim);
  const double settle = sim.settle;
  const double capture = sim.capture;
  ic->coordinates = mm.p0;
  ic->velocities = mm.v0;
  ic->elastic = sim.start == SimOptions::Start::kStatic
                    ? multibody::ElasticInitialState::kStaticEquilibrium
                    : multibody::ElasticInitialState::kUndeformed;
  const RunWindow window = mm.recipe->SetUpRun(sim, mm, ic, &opt);
  const double t_capture_start = window.capture_start;
  opt.t_start = 0.0;
  opt.sample_start = opt.start_sampling_at_index ? settle : t_capture_start;
  opt.t_end = t_capture_start + capture + window.extra_time;
  const int max_steps = sim.max_steps;
  opt.max_steps = max_steps > 0 ? max_steps : std::lround(1e6 * (opt.t_end - opt.t_start)) + 100000;
  if (const double budget = sim.max_wall_time; budget > 0.0) {
    // Capped at 10⁹ s (32 years), which keeps the conversion to clock ticks defined.
    opt.deadline = wall0 + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                               std::chrono::duration<double>(std::min(budget, 1e9)));
  }
  opt.time_elements = profile;
  opt.integrator.time_calls = profile;
  opt.integrator.count_step_limiting = profile;
  opt.stop = stop;
  opt.Validate(m);
  return opt;
}

/// sim.start = steady (a slider-crank with a flexible rod, checked by CheckRunInput): integrates
/// from `ic` revolution by revolution and returns the state at the crank index where the rod's
/// elastic state repeats; `steady` receives how it was found, `status` the last integration's.
///
/// The rod's elastic coordinates at kSteadySamples points of a revolution must repeat those of
/// the previous one to 1000 · sim.rel_tol of their peak (kept within [1e-6, 1e-2]). The repeat
/// cannot be closer than the integration error: on the flexible rig (ideal joint, 200 rpm)
/// successive revolutions of a long run differ by 2e-4 of the peak at rel_tol 1e-6 and 1.5e-8
/// at 1e-8.
multibody::ConsistentState FindSteadyState(const SimOptions& sim, const MechanismModel& mm,
                                           const multibody::SimulationOptions& opt,
                                           const multibody::InitialConditionSpec& ic,
                                           multibody::RunData* data,
                                           multibody::SimulationStatus* status,
                                           nlohmann::json* steady) {
  const multibody::Mechanism& m = mm.mechanism;
  const int max_revolutions = sim.steady_revolutions;
  constexpr int kSteadySamples = 16;
  const double tolerance = std::clamp(1e3 * opt.integrator.rel_tol, 1e-6, 1e-2);
  multibody::ConsistentState state = multibody::ComputeConsistentState(m, data, 0.0, ic);
  const double period = kTwoPi / mm.drive.speed;
  const double to_index = WrapToTwoPi(sim.index_angle - mm.drive.initial_angle);
  const double t_first_index = to_index * period / kTwoPi;
  // The rod's elastic state: its elastic coordinates q (reduced rod), the nodes' deflections
  // from the chord (exact rod).
  const std::optional<study::ExactRodView> exact_view =
      mm.exact ? std::optional<study::ExactRodView>(std::in_place, m, *mm.exact) : std::nullopt;
  const int q0 = mm.rod ? m.coordinate(mm.conrod, multibody::kFirstMode) : 0;
  const int n = mm.rod ? mm.rod->num_coordinates() : exact_view->num_nodes();
  Mat previous, now(kSteadySamples, n);
  Vec state_row(n);
  multibody::SimulationOptions rev = opt;
  rev.start_sampling_at_index = false;
  rev.sample_rate = kSteadySamples / period;
  double change = std::numeric_limits<double>::infinity();  // no previous revolution yet
  int revolutions = 0;
  for (; revolutions < max_revolutions && change > tolerance; ++revolutions) {
    // Segment r ends at the (r+1)-th index time after t_first_index; its last revolution is
    // sampled.
    rev.t_end = t_first_index + (revolutions + 1) * period;
    rev.sample_start = rev.t_end - period + period / kSteadySamples;
    multibody::ConsistentState next;
    int k = 0;
    multibody::SimulationCallbacks c2;
    c2.on_sample = [&](const SampleView& s) {
      if (k < kSteadySamples) {
        if (exact_view) {
          exact_view->ElasticState(s.y(), state_row.data());
        } else {
          state_row = Eigen::Map<const Vec>(s.y() + q0, n);
        }
        now.row(k++) = state_row.transpose();
      }
      next.t = s.t();
      next.y = Eigen::Map<const Vec>(s.y(), m.size());
      next.yp = Eigen::Map<const Vec>(s.yp(), m.size());
    };
    *status = multibody::Simulate(m, data, state, rev, c2);
    if (!status->ok() || k < kSteadySamples) break;
    if (previous.size() > 0)
      change = (now - previous).cwiseAbs().maxCoeff() / std::max(now.cwiseAbs().maxCoeff(), 1e-300);
    previous = now;
    state = next;
  }
  *steady = {{"revolutions", revolutions},
             {"relative_change", change},
             {"tolerance", tolerance},
             {"converged", change <= tolerance}};
  return state;
}

/// The largest |stress| over the gauges (channels stress_*) in each revolution [Pa]; empty
/// without gauges.
std::vector<double> GaugeStressPeaks(const study::TimeSeries& ts,
                                     const std::vector<study::SampleRange>& revolutions) {
  std::vector<double> peaks;
  for (const study::Channel& c : ts.channels()) {
    if (c.name.rfind("stress_", 0) != 0) continue;
    peaks.resize(revolutions.size(), 0.0);
    for (size_t k = 0; k < revolutions.size(); ++k) {
      for (size_t i = revolutions[k].begin; i < revolutions[k].end; ++i)
        peaks[k] = std::max(peaks[k], std::abs(c.values[i]));
    }
  }
  return peaks;
}

}  // namespace

std::vector<std::pair<std::string, std::vector<double>>> PerRevolutionSeries(const RunResult& run) {
  std::vector<std::pair<std::string, std::vector<double>>> s;
  if (!run.slider_acceleration || !run.bearing_force) return s;
  s.emplace_back("slider_acceleration_positive [m/s^2]", run.slider_acceleration->positive_peaks);
  s.emplace_back("slider_acceleration_negative [m/s^2]", run.slider_acceleration->negative_peaks);
  s.emplace_back("bearing_force [N]", run.bearing_force->positive_peaks);
  if (!run.gauge_stress_peaks.empty()) s.emplace_back("gauge_stress [Pa]", run.gauge_stress_peaks);
  return s;
}

namespace {

/// The per-revolution series of a run, without their names.
std::vector<std::vector<double>> WindowSeries(const RunResult& run) {
  std::vector<std::vector<double>> v;
  for (auto& [name, x] : PerRevolutionSeries(run)) v.push_back(std::move(x));
  return v;
}

/// A crank's per-revolution statistics of the run's channels: the slider acceleration's and the
/// bearing force's (one split into revolutions for both, and, through the twin's, the
/// amplification), the gauge stress's peaks. Nothing for fewer than 3 samples.
void SummariseRevolutions(double index_angle, RunResult* out) {
  const study::TimeSeries& ts = out->channels;
  if (ts.num_samples() <= 2) return;
  const study::SampleRange all = ts.all();
  const std::vector<study::SampleRange> revolutions =
      study::SplitRevolutions(ts.values("crank_angle"), index_angle, all);
  out->slider_acceleration =
      study::CalcSignalSummary(ts.values("slider_acceleration"), all, revolutions);
  out->bearing_force = study::CalcSignalSummary(ts.values("bearing_force"), all, revolutions);
  out->gauge_stress_peaks = GaugeStressPeaks(ts, revolutions);
}

/// The summary of a finished run `out` (its channels, impacts and status set): per-revolution
/// statistics of a crank's run, the channel summaries, the steady start, the impacts, the
/// integrator's counters.
void SummariseRun(const Config& cfg, const SimOptions& sim, const MechanismModel& mm,
                  const Recorder& rec, const nlohmann::json& gauges, const nlohmann::json& steady,
                  const nlohmann::json& steady_window, study::ImpactLogger* impacts, bool profile,
                  std::chrono::steady_clock::time_point wall0, RunResult* out_ptr) {
  const multibody::Mechanism& m = mm.mechanism;
  RunResult& out = *out_ptr;
  if (mm.recipe->turns_a_crank()) SummariseRevolutions(sim.index_angle, &out);
  out.summary = Summarise(out, rec, cfg, mm);
  if (out.slider_acceleration) {
    const study::WindowClassification w = study::ClassifyWindow(WindowSeries(out));
    out.summary["regime"] = {
        {"window", study::ToString(w.regime)}, {"period [revolutions]", w.period},
        {"outlier_revolutions", w.outliers},   {"relative_spread", w.relative_spread},
        {"zero_one_k", w.zero_one_k},          {"reason", w.reason}};
  }
  if (!steady_window.is_null()) {
    out.summary["steady_window"] = steady_window;
    if (!steady_window["stationary"].get<bool>()) {
      out.summary["warnings"].push_back(
          "sim.steady_window: the captured window is not stationary (" +
          steady_window["worst_series"].get<std::string>() +
          ": its first revolutions differ from the rest by more than " +
          FormatValue(steady_window["worst_limit"].get<double>()) +
          ") and the next window would start after sim.max_settle = " +
          FormatValue(sim.max_settle) +
          " s; the figures may carry a transient or an intermittent regime");
    }
  }
  out.summary["gauges"] = gauges;
  if (!steady.is_null()) {
    out.summary["steady_start"] = steady;
    if (!steady["converged"].get<bool>()) {
      out.summary["warnings"].push_back(
          "sim.start = steady: the rod's elastic state did not repeat to " +
          FormatValue(steady["tolerance"].get<double>()) + " within " +
          std::to_string(steady["revolutions"].get<int>()) + " revolutions (last change " +
          FormatValue(steady["relative_change"].get<double>()) +
          " of its peak; a clearance joint's contact motion need not be periodic); the capture "
          "starts there");
    }
  }
  if (impacts && out.channels.num_samples() > 2) {
    out.impacts = impacts->Finish();
    const study::ImpactStatistics st = study::CalcImpactStatistics(out.impacts);
    const auto th = out.channels.values("crank_angle");
    const double revs = (th.back() - th.front()) / (2.0 * std::numbers::pi);
    out.summary["impacts"] = {{"count", st.count},
                              {"incomplete", st.incomplete},
                              {"per_revolution", revs > 0 ? st.count / revs : 0.0},
                              {"max_peak_force [N]", st.max_peak_force},
                              {"median_peak_force [N]", st.median_peak_force},
                              {"max_approach_velocity [m/s]", st.max_approach_velocity},
                              {"max_peak_penetration [m]", st.max_peak_penetration},
                              {"mean_duration [s]", st.mean_duration},
                              {"total_dissipated_energy [J]", st.total_dissipated_energy}};
    for (const contact::ResolvedParameter& p : mm.joint_parameters) {
      out.summary["joint_parameters"][p.name] = {
          {"value", p.value}, {"unit", p.unit}, {"source", p.source}};
    }
  }
  out.summary["integrator"] = StatusJson(out.status, profile);
  if (const std::string note = multibody::CaughtStepControlNote(out.status.stats); !note.empty())
    out.summary["warnings"].push_back("integrator: " + note);
  for (size_t e = 0; e < out.status.element_seconds.size(); ++e) {  // RunOutputOptions::profile
    nlohmann::json& t =
        out.summary["integrator"]["element_time [s]"][m.elements()[e].element->type_name()];
    t = (t.is_null() ? 0.0 : t.get<double>()) + out.status.element_seconds[e];
  }
  out.summary["samples"] = out.channels.num_samples();
  out.summary["capture_start [s]"] = out.channels.num_samples() ? out.channels.start_time() : 0.0;
  out.summary["wall_time [s]"] =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
}

/// One captured window of a run: its record, impact log and ParaView frames, the integrator's
/// status, and (when asked) the state at its last solution point.
struct Window {
  Recorder rec;
  nlohmann::json gauges;
  std::optional<study::ImpactLogger> impacts;  // clearance runs: every located contact event
  std::optional<study::VtkRecorder> vtk;
  multibody::SimulationStatus status;
  std::optional<multibody::ConsistentState> end;
};

/// A run of `mm`, built from `cfg` (BuildMechanism(cfg, rod, ideal_joint)), with `sim` from
/// CheckRunInput(cfg, the run's mechanism); `wall0` is when its building began
/// (sim.max_wall_time counts from there); `keep_channel`: RunOutputOptions::keep_channel.
RunResult RunOne(const Config& cfg, const SimOptions& sim, MechanismModel mm, bool ideal_joint,
                 std::chrono::steady_clock::time_point wall0, MechanismModel* model_out,
                 const VtkOptions* vtk_options = nullptr, bool profile = false,
                 const std::atomic<bool>* stop = nullptr,
                 const std::function<bool(const std::string&)>& keep_channel = nullptr) {
  const multibody::Mechanism& m = mm.mechanism;
  multibody::InitialConditionSpec ic;
  multibody::SimulationOptions opt = RunOptions(sim, mm, wall0, profile, stop, &ic);
  const double capture = sim.capture;
  const double rate = opt.sample_rate;
  const long max_samples = static_cast<long>(std::floor(capture * rate + 1e-9));
  // sim.steady_window: a crank's window is tested, and replaced by the next while it is not
  // stationary; each window then keeps its end state.
  const bool test_window =
      sim.steady_window && sim.start != SimOptions::Start::kSteady && mm.recipe->turns_a_crank();
  // The channels alone (no samples): bad output.* keys fail before any integration (checked on
  // the real run: its twin has fewer channels); a run that captures nothing summarises these.
  Recorder no_window;
  nlohmann::json no_gauges;
  DefineChannels(cfg, mm, &no_window, &no_gauges, nullptr);
  if (!ideal_joint) (void)ReadOutputSelection(cfg, opt.sample_rate, &no_window.names());
  const auto run_data = std::make_unique<multibody::RunData>(m);
  // Integrates from `from` (the initial conditions if empty) with `o`, capturing one window.
  auto capture_window = [&](const multibody::SimulationOptions& o,
                            const std::optional<multibody::ConsistentState>& from) {
    auto w = std::make_unique<Window>();
    Recorder& rec = w->rec;
    if (mm.clearance.index >= 0) w->impacts.emplace();
    study::ImpactLogger* impacts = w->impacts ? &*w->impacts : nullptr;
    DefineChannels(cfg, mm, &rec, &w->gauges, impacts);
    if (keep_channel) {
      // A crank's gauge stresses give the per-revolution peaks (PerRevolutionSeries).
      const bool crank = mm.recipe->turns_a_crank();
      rec.KeepOnly([&](const std::string& name) {
        return std::find(std::begin(kSummaryChannels), std::end(kSummaryChannels), name) !=
                   std::end(kSummaryChannels) ||
               (crank && name.rfind("stress_", 0) == 0) || keep_channel(name);
      });
    }
    rec.Reserve(static_cast<size_t>(max_samples));
    // ParaView frames ride on the same samples: capture sample k is offered before it is
    // recorded.
    if (vtk_options) w->vtk.emplace(cfg, mm, *vtk_options, rate);
    multibody::SimulationCallbacks cb;
    double t_last_sample = 0.0;
    cb.on_sample = [&](const SampleView& sv) {
      if (static_cast<long>(rec.size()) < max_samples) {
        if (w->vtk) w->vtk->Offer(static_cast<long>(rec.size()), sv);
        rec.Record(sv);
        t_last_sample = sv.t();
      }
    };
    // The joint at the end of the last step searched for peaks (the step's next reported point).
    std::optional<multibody::ClearanceResponse> step_end;
    double step_end_time = 0.0;
    // Every solution point overwrites the same storage: no allocation in a step after the first.
    auto keep_end = [&](const SampleView& sv) {
      multibody::ConsistentState& e = w->end ? *w->end : w->end.emplace();
      e.t = sv.t();
      e.y = Eigen::Map<const Vec>(sv.y(), m.size());
      e.yp = Eigen::Map<const Vec>(sv.yp(), m.size());
    };
    if (impacts) {
      // The impact log also sees every integrator step and located event of the capture window
      // (from its first sample to its last); the samples reach it through the channels.
      cb.on_step = [&,
                    crank_theta = m.coordinate(mm.crank, multibody::kTheta)](const SampleView& sv) {
        if (test_window) keep_end(sv);
        const std::optional<multibody::ClearanceResponse> searched =
            std::exchange(step_end, std::nullopt);
        if (rec.size() == 0 ||
            (static_cast<long>(rec.size()) >= max_samples && sv.t() > t_last_sample))
          return;
        impacts->Observe(
            study::MakeContactPoint(sv.t(), sv.coordinate(crank_theta),
                                    searched && step_end_time == sv.t()
                                        ? *searched
                                        : multibody::CalcClearanceResponse(sv, mm.clearance)));
      };
      // Inside an impact, the peak force and penetration are located within each step (its
      // interpolating polynomial), not taken at the solution points, which can be 5e-4 low.
      cb.on_step_interval = [&](const multibody::StepInterpolant& step) {
        if (rec.size() == 0 ||
            (static_cast<long>(rec.size()) >= max_samples && step.t_begin() >= t_last_sample))
          return;
        step_end = study::LocateImpactPeaks(step, mm.clearance, impacts);
        step_end_time = step.t_end();
      };
    } else if (test_window) {
      cb.on_step = keep_end;
    }
    multibody::RunData& data = *run_data;
    w->status = from ? multibody::Simulate(m, &data, *from, o, cb)
                     : multibody::Simulate(m, &data, ic, o, cb);
    return w;
  };

  RunResult out;
  nlohmann::json steady;  // sim.start = steady: how the periodic state was found
  std::unique_ptr<Window> w;
  if (sim.start == SimOptions::Start::kSteady) {
    const multibody::ConsistentState state =
        FindSteadyState(sim, mm, opt, ic, run_data.get(), &out.status, &steady);
    if (out.status.ok()) {
      opt.sample_start = state.t;
      opt.t_end = state.t + capture;
      opt.start_sampling_at_index = false;
      w = capture_window(opt, state);
    }
  } else {
    w = capture_window(opt, std::nullopt);
  }
  nlohmann::json steady_window;  // sim.steady_window: the stationarity test of the window
  if (w) {
    out.channels = w->rec.Finish(rate);
    out.status = w->status;
  }
  for (int windows = 1; w && test_window; ++windows) {
    // The window's per-revolution peaks, as the summary will take them.
    SummariseRevolutions(sim.index_angle, &out);
    const auto series = PerRevolutionSeries(out);
    const study::StationarityVerdict verdict = study::TestStationarity(WindowSeries(out));
    steady_window = {{"stationary", verdict.stationary},
                     {"windows", windows},
                     {"capture_start [s]", out.channels.start_time()},
                     {"max_settle [s]", sim.max_settle},
                     {"revolutions", series.empty() ? 0 : series.front().second.size()},
                     {"tested", verdict.worst >= 0},
                     {"alpha", 0.01},
                     {"floor", study::kStationarityFloor}};
    for (size_t k = 0; k < series.size(); ++k) {
      const study::StationarityResult& r = verdict.series[k];
      steady_window["series"][series[k].first] = {{"leading_revolutions (0: trend)", r.leading},
                                                  {"leading_mean", r.first_mean},
                                                  {"rest_mean", r.second_mean},
                                                  {"limit", r.limit},
                                                  {"stationary", r.stationary}};
    }
    if (verdict.worst >= 0) {
      steady_window["worst_series"] = series[static_cast<size_t>(verdict.worst)].first;
      steady_window["worst_limit"] = verdict.series[static_cast<size_t>(verdict.worst)].limit;
    }
    if (verdict.stationary || !out.status.ok() || !w->end) break;
    // The next window: this one becomes settling.
    SimOptions next_sim = sim;
    next_sim.settle = w->end->t;
    multibody::InitialConditionSpec unused;
    multibody::SimulationOptions next = RunOptions(next_sim, mm, wall0, profile, stop, &unused);
    const double next_start = next.start_sampling_at_index ? w->end->t : next.sample_start;
    if (next_start > sim.max_settle) break;
    next.t_start = w->end->t;
    std::unique_ptr<Window> later = capture_window(next, *w->end);
    w = std::move(later);
    out.channels = w->rec.Finish(rate);
    out.status = w->status;
  }
  if (w) {
    if (w->vtk) out.vtk = w->vtk->Finish();
    SummariseRun(cfg, sim, mm, w->rec, w->gauges, steady, steady_window,
                 w->impacts ? &*w->impacts : nullptr, profile, wall0, &out);
  } else {
    out.channels = no_window.Finish(rate);
    SummariseRun(cfg, sim, mm, no_window, no_gauges, steady, steady_window, nullptr, profile, wall0,
                 &out);
  }
  if (model_out) *model_out = std::move(mm);
  return out;
}

}  // namespace

RunResult RunSimulation(const Config& cfg, std::shared_ptr<const fem::ReducedRod> rod,
                        bool ideal_joint, const RunOutputOptions& outputs) {
  std::optional<VtkOptions> vtk_options;
  if (outputs.record_vtk) vtk_options = ReadVtkOptions(cfg);  // bad vtk.* keys fail before any work
  const auto wall0 = std::chrono::steady_clock::now();
  MechanismModel built = BuildMechanism(cfg, std::move(rod), ideal_joint);
  // The ideal-joint twin of a clearance run: same mechanism, same rod, same capture window. With
  // a second core and no twin cache (a sweep's or study's workers already fill the cores), it
  // runs beside the run, on the run's rod.
  const bool needs_twin = built.clearance.index >= 0 && built.recipe->turns_a_crank();
  const SimOptions sim = CheckRunInput(cfg, built);  // a bad input starts no run and no twin
  // A twin shared through the cache keeps every channel: other runs read it.
  const Config& twin_cfg = outputs.twin_input ? *outputs.twin_input : cfg;
  const SimOptions twin_sim = outputs.twin_input ? ReadSimOptions(twin_cfg) : sim;
  auto run_twin = [twin_cfg, twin_sim, stop = outputs.stop,
                   keep = outputs.twins ? nullptr : outputs.keep_channel](
                      std::shared_ptr<const fem::ReducedRod> twin_rod) {
    const auto twin_wall0 = std::chrono::steady_clock::now();
    return std::make_shared<const RunResult>(
        RunOne(twin_cfg, twin_sim, BuildMechanism(twin_cfg, std::move(twin_rod), true), true,
               twin_wall0, nullptr, nullptr, false, stop, keep));
  };
  std::future<std::shared_ptr<const RunResult>> twin_beside;
  if (needs_twin && outputs.twins == nullptr && std::thread::hardware_concurrency() > 1)
    twin_beside = std::async(std::launch::async, run_twin, built.rod);
  MechanismModel mm;
  RunResult out = RunOne(cfg, sim, std::move(built), ideal_joint, wall0, &mm,
                         vtk_options ? &*vtk_options : nullptr, outputs.profile, outputs.stop,
                         outputs.keep_channel);
  if (mm.clearance.index < 0 || out.channels.num_samples() < 3) return out;
  bool computed = false;
  auto compute_twin = [&] {
    computed = true;
    if (twin_beside.valid()) return twin_beside.get();
    return run_twin(mm.rod);
  };
  const std::shared_ptr<const RunResult> twin =
      outputs.twins ? outputs.twins->Get(twin_cfg, compute_twin) : compute_twin();
  out.summary["ideal"] = twin->summary;
  out.summary["ideal"]["reused"] = !computed;
  if (twin->ok() && twin->channels.num_samples() == out.channels.num_samples() &&
      out.slider_acceleration &&
      twin->slider_acceleration) {  // (and bearing_force: both are set together)
    const study::LoadAmplification a =
        study::CalcLoadAmplification(*out.slider_acceleration, *twin->slider_acceleration);
    auto num = [](double v) {
      return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
    };
    nlohmann::json amp = {{"slider_acceleration_positive", num(a.positive)},
                          {"slider_acceleration_negative", num(a.negative)},
                          {"slider_acceleration_positive_p95", num(a.positive_p95)},
                          {"slider_acceleration_negative_p95", num(a.negative_p95)}};
    // Bearing force: the ideal joint's reaction against the clearance joint's contact force, both
    // |F| on the bush (channel bearing_force), whole-window peaks (bearing force ≥ 0: its
    // peak_positive is its maximum) and, as for the acceleration, the ratio of the 95th
    // percentiles of the per-revolution peaks. The whole-window peak is one impact, which a
    // chaotic contact history can move by tens of percent between tolerances; the p95 ratio is
    // the figure to compare.
    const study::SignalSummary& fr = *out.bearing_force;
    const study::SignalSummary& fi = *twin->bearing_force;
    amp["bearing_force"] = num(fi.peak_positive > 0 ? fr.peak_positive / fi.peak_positive : NAN);
    amp["bearing_force_peak_real [N]"] = fr.peak_positive;
    amp["bearing_force_peak_ideal [N]"] = fi.peak_positive;
    amp["bearing_force_p95"] = num(fi.positive.p95 > 0 ? fr.positive.p95 / fi.positive.p95 : NAN);
    out.summary["load_amplification"] = amp;
  }
  out.ideal =
      std::shared_ptr<const study::TimeSeries>(twin, &twin->channels);  // lives with the twin
  return out;
}

std::string TwinKey(const Config& cfg) {
  std::string key;
  for (const Config::Resolved& r : cfg.Resolve()) {
    if (r.key.rfind("joint.", 0) != 0) key += r.key + "=" + r.value + ";";
  }
  return key;
}

std::shared_ptr<const RunResult> TwinCache::Get(
    const Config& cfg, const std::function<std::shared_ptr<const RunResult>()>& compute) {
  return twins_.Get(TwinKey(cfg), compute);
}

Config TightenedForCheck(const Config& cfg) {
  Config check = cfg;
  for (const char* key : {"sim.rel_tol", "sim.abs_tol"}) {
    check.Set(key, FormatValue(cfg.Quantity(key) / 100.0));
  }
  try {
    (void)IntegratorOptions(ReadSimOptions(check));
  } catch (const InputError& e) {
    // The user's value is named; the derived one is in the rule.
    const bool tolerance = e.key() == "sim.rel_tol" || e.key() == "sim.abs_tol";
    throw InputError("--check",
                     e.key() + " = " + (tolerance ? FormatValue(cfg.Quantity(e.key())) : e.value()),
                     "the check runs at 100x tighter tolerances (" + e.key() + " = " + e.value() +
                         "), which " + e.rule() + "; loosen the run's own tolerance");
  }
  return check;
}

nlohmann::json CompareHeadlineFigures(const nlohmann::json& summary,
                                      const nlohmann::json& reference) {
  // Summary paths of the figures users quote, with their units.
  static const std::vector<std::pair<std::vector<std::string>, std::string>> kFigures = {
      {{"slider_acceleration", "peak_positive"}, "m/s^2"},
      {{"slider_acceleration", "peak_negative"}, "m/s^2"},
      {{"slider_acceleration", "per_revolution_abs", "p95"}, "m/s^2"},
      {{"load_amplification", "slider_acceleration_positive"}, "1"},
      {{"load_amplification", "slider_acceleration_negative"}, "1"},
      {{"load_amplification", "slider_acceleration_positive_p95"}, "1"},
      {{"load_amplification", "slider_acceleration_negative_p95"}, "1"},
      {{"load_amplification", "bearing_force"}, "1"},
      {{"load_amplification", "bearing_force_peak_real [N]"}, "N"},
      {{"rod", "peak_gauge_stress [Pa]"}, "Pa"},
  };
  auto find = [](const nlohmann::json& j,
                 const std::vector<std::string>& path) -> const nlohmann::json* {
    const nlohmann::json* node = &j;
    for (const std::string& k : path) {
      if (!node->is_object() || !node->contains(k)) return nullptr;
      node = &(*node)[k];
    }
    return node->is_number() ? node : nullptr;
  };
  nlohmann::json out = {{"figures", nlohmann::json::object()}};
  double worst = 0.0;
  std::string worst_name;
  for (const auto& [path, unit] : kFigures) {
    const nlohmann::json* a = find(summary, path);
    const nlohmann::json* b = find(reference, path);
    if (a == nullptr || b == nullptr) continue;
    std::string name;
    for (const std::string& k : path) name += (name.empty() ? "" : ".") + k;
    const double value = a->get<double>(), ref = b->get<double>();
    const double diff = ref != 0.0 ? 100.0 * (value - ref) / std::abs(ref) : 0.0;
    out["figures"][name] = {
        {"value", value}, {"reference", ref}, {"unit", unit}, {"difference [%]", diff}};
    if (std::abs(diff) >= std::abs(worst)) {
      worst = diff;
      worst_name = name;
    }
  }
  out["max_difference [%]"] = worst;
  out["max_difference_figure"] = worst_name;
  return out;
}

void AddAccuracyCheck(const Config& check_cfg, RunResult* run, const std::atomic<bool>* stop) {
  RunOutputOptions outputs;
  outputs.stop = stop;
  outputs.keep_channel = [](const std::string&) { return false; };  // its summary is compared
  const RunResult reference = RunSimulation(check_cfg, nullptr, false, outputs);
  nlohmann::json check = CompareHeadlineFigures(run->summary, reference.summary);
  check["rel_tol"] = check_cfg.Quantity("sim.rel_tol");
  check["abs_tol"] = check_cfg.Quantity("sim.abs_tol");
  check["reference_outcome"] = multibody::ToString(reference.status.outcome);
  run->summary["accuracy_check"] = check;
}

}  // namespace flexrod
