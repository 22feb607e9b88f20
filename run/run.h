// run/run.h — one run: one mechanism at one operating point, integrated, sampled at the
// rig's rate inside the capture window (after settling, triggered at the index angle), turned
// into unit-carrying channels and a summary. What does not live here: the equations
// (multibody/), the signal analysis (signals/signals.h), the files a run writes
// (io/run_writer.h), sweeps (sweep/sweep.h).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "common/once_cache.h"
#include "input/config.h"
#include "mechanisms/drawing.h"
#include "mechanisms/impact_log.h"
#include "mechanisms/mechanism_model.h"
#include "multibody/simulate.h"
#include "signals/regimes.h"
#include "signals/signals.h"
#include "signals/timeseries.h"

namespace flexrod {

struct RunResult {
  study::TimeSeries channels{1.0, 0.0};  ///< the captured window (rig sample rate)
  multibody::SimulationStatus status;
  nlohmann::json summary;  ///< peaks, RMS, statistics, energy, wall time,
                           ///< and load_amplification for clearance runs
  /// The ideal-joint twin's channels (clearance runs; shared with other runs when the twin
  /// came from a TwinCache).
  std::shared_ptr<const study::TimeSeries> ideal;
  /// Slider-cranks: slider_acceleration and bearing_force over the capture and its complete
  /// revolutions (summary "slider_acceleration"; the load amplification's inputs).
  std::optional<study::SignalSummary> slider_acceleration, bearing_force;
  /// Slider-cranks with a gauged rod: the largest |stress| over the gauges in each complete
  /// revolution of the capture, in time order [Pa].
  std::vector<double> gauge_stress_peaks;
  std::vector<study::Impact> impacts;   ///< impact log of the captured window (clearance runs)
  std::optional<study::VtkSeries> vtk;  ///< ParaView frames of the captured window, if requested
  bool ok() const { return status.ok(); }
};

/// The per-revolution series of a crank's run (one value per complete revolution of the
/// capture, in time order), named with their units: the slider acceleration's positive and
/// negative peaks (magnitudes), the bearing force's peak, the gauge stress's (with gauges).
/// Empty for a run without slider-crank channels.
std::vector<std::pair<std::string, std::vector<double>>> PerRevolutionSeries(const RunResult& run);

/// Checks every input a run of `mm` (BuildMechanism(cfg, ...)) reads beyond the mechanism's
/// own keys: sim.* (tolerances, settle, a capture of at least 2 samples, the start), the probe
/// and gauge positions on the rod, the output.* selection. Throws InputError naming the key,
/// the value and the rule. Sweeps and studies call it for every run before any run starts.
/// Returns sim.*, checked.
SimOptions CheckRunInput(const Config& cfg, const MechanismModel& mm);

/// The names of the channels a run of `mm` records (RunResult::channels), in their order,
/// without running it.
std::vector<std::string> RunChannelNames(const Config& cfg, const MechanismModel& mm);

/// What a clearance run's ideal-joint twin depends on: every resolved input except the
/// small-end joint's keys (joint.*), since the twin's joint is ideal. Runs with equal keys (a
/// study or sweep over clearance, contact law, friction, restitution, materials of the pin and
/// bush) have the same twin.
std::string TwinKey(const Config& cfg);

/// Ideal-joint twins shared by the clearance runs of a study or sweep, keyed by TwinKey: the
/// first run computes its twin, runs with the same key reuse it. Keeps the max(4, `keep`) most
/// recently used twins (a twin holds its whole capture: tens of MB at 100 kHz). Thread-safe.
class TwinCache {
 public:
  explicit TwinCache(std::size_t keep = 4) : twins_(std::max<std::size_t>(keep, 4)) {}
  /// The twin run of `cfg`, from compute() if no run asked for its key (or it was evicted).
  std::shared_ptr<const RunResult> Get(
      const Config& cfg, const std::function<std::shared_ptr<const RunResult>()>& compute);
  int num_computed() const { return static_cast<int>(twins_.num_computed()); }

 private:
  OnceCache<std::shared_ptr<const RunResult>> twins_;
};

/// Optional outputs of a run beyond the channels, and the twin cache. Sweeps and studies pass
/// a TwinCache; otherwise the defaults (nothing extra).
struct RunOutputOptions {
  /// Record ParaView frames (vtk.* keys, run/vtk.h) of the captured window of the run (not
  /// of its ideal-joint twin) into RunResult::vtk (also after a numerical failure: the frames
  /// up to it). The vtk.* keys are checked before any work starts. io/run_writer.h writes them.
  bool record_vtk{false};
  /// Profile the run (not its twin): time each force element (multibody::SimulationOptions::
  /// time_elements) and the integrator's residuals, Jacobians and linear solves
  /// (IntegratorOptions::time_calls), and report them in summary["integrator"]
  /// ("element_time [s]" per element type, "residual_time [s]", "jacobian_time [s]",
  /// "linear_solve_time [s]"). Off by default: the clock reads cost a few percent.
  bool profile{false};
  /// Share the ideal-joint twin with the other runs using this cache (nullptr: compute it).
  /// summary["ideal"]["reused"] says whether the twin came from an earlier run.
  TwinCache* twins{nullptr};
  /// The input whose ideal-joint twin this run shares (through `twins`, keyed by its TwinKey):
  /// an ensemble's members share member 0's (run/ensemble.h). nullptr: the run's own input.
  const Config* twin_input{nullptr};
  /// Polled by the integrator (multibody::SimulationOptions::stop), also in the ideal-joint
  /// twin: once true, the run stops with outcome kInterrupted. nullptr: never stops.
  const std::atomic<bool>* stop{nullptr};
  /// The channels whose samples RunResult::channels keeps (and its twin's, unless the twin is
  /// shared through `twins`), beside those the run's own summary reads (crank angle, slider
  /// acceleration, bearing force). nullptr: every channel. Every channel's peak and RMS stay in
  /// summary["channels"] either way, and the summary does not change. `flexrod run` keeps what
  /// its files read (io/run_writer.h ChannelsTheFilesRead).
  std::function<bool(const std::string&)> keep_channel;
};

/// Runs the input. `rod` (optional) is a reduced rod to reuse; `ideal_joint` forces an ideal
/// small-end joint. A clearance run also runs its ideal-joint twin (same rod, same capture
/// window) and reports the load amplification = peak |slider acceleration| real / ideal per
/// direction (and on the per-revolution 95th percentiles), and the bearing-force ratio.
/// A numerical failure is reported in the status; the channels up to it are kept.
RunResult RunSimulation(const Config& cfg, std::shared_ptr<const fem::ReducedRod> rod = nullptr,
                        bool ideal_joint = false, const RunOutputOptions& outputs = {});

/// The accuracy estimate of `flexrod run --check`: `cfg` with sim.rel_tol and sim.abs_tol
/// 100 times tighter (InputError if that goes below the integrator's floor).
Config TightenedForCheck(const Config& cfg);

/// The accuracy check of `flexrod run --check`: runs `check_cfg` (TightenedForCheck of the
/// run's input) and puts the headline figures' differences (CompareHeadlineFigures) with the
/// tolerances and the reference run's outcome into run->summary["accuracy_check"]. `stop` as in
/// RunOutputOptions.
void AddAccuracyCheck(const Config& check_cfg, RunResult* run,
                      const std::atomic<bool>* stop = nullptr);

/// The headline figures of a run summary (peak and p95 of the per-revolution peak slider
/// acceleration, the load amplifications, the peak bearing force, the peak gauge stress),
/// each with its value, the reference run's and their relative difference [%], under
/// "figures"; "max_difference [%]" and the figure that has it. Figures either summary lacks
/// (a rigid rod has no gauges, an ideal joint no amplification) are left out.
nlohmann::json CompareHeadlineFigures(const nlohmann::json& summary,
                                      const nlohmann::json& reference);

}  // namespace flexrod
