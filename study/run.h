// study/run.h — one run: one mechanism at one operating point, integrated, sampled at the
// rig's rate inside the capture window (after settling, triggered at the index angle), turned
// into unit-carrying channels and a summary; and the files a run writes (resolved input,
// channels CSV, summary JSON, plot). What does not live here: the equations (multibody/),
// the signal analysis (study/signals.h), sweeps (study/sweep.h).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "multibody/simulate.h"
#include "study/config.h"
#include "study/slider_crank.h"
#include "study/timeseries.h"

namespace flexrod {

struct RunResult {
  study::TimeSeries channels{1.0, 0.0};   ///< the captured window (rig sample rate)
  multibody::SimulationStatus status;
  nlohmann::json summary;                 ///< peaks, RMS, statistics, energy, wall time
  bool ok() const { return status.ok(); }
};

/// Runs the input. `rod` (optional) is a reduced rod to reuse; `ideal_joint` forces the ideal
/// twin. A numerical failure is reported in the status; the channels up to it are kept.
RunResult RunSimulation(const Config& cfg, std::shared_ptr<const fem::ReducedRod> rod = nullptr,
                        bool ideal_joint = false);

/// Writes resolved.toml, channels.csv, summary.json and slider_acceleration.png into `dir`.
/// Each file is written whole (temporary + rename). Returns the plot status message.
void WriteRunFiles(const std::string& dir, const Config& cfg, const RunResult& run);

}  // namespace flexrod
