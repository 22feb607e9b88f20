// io/run_files.h — the files a run writes into its output directory:
//   resolved.toml  every input key, defaults filled in, SI, derived contact parameters as notes
//   summary.json   RunResult::summary
//   run.h5         (output.format hdf5, the default) the run in the layout of a run in the sweep
//                  store (sweep/sweep_store.h: attributes, summary, inflection_points, poincare,
//                  spectrum, channels/<name> chunked, shuffled and deflated, "unit" on every
//                  dataset), plus
//                    ideal/channels/<name>  the ideal-joint twin's channels (clearance runs), or
//                                           an external link to the run.h5 that holds them
//                    impacts/<column>       the impact log (mechanisms/impact_log.h ImpactColumns)
//   channels.csv, ideal/channels.csv, impacts.csv   (output.format csv)
// What does not live here: running (run/run.h), the sweep store (sweep/sweep_store.h).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "input/config.h"
#include "input/output_selection.h"
#include "run/run.h"
#include "signals/timeseries.h"

namespace flexrod {

/// The selected channels (those the record has) at every stride-th sample.
study::TimeSeries SelectChannels(const study::TimeSeries& ts, const OutputSelection& sel);

/// Writes the run's files into `dir` (created if missing), each whole (temporary + rename).
/// `shared_twin_dir` (optional) is the output directory of an earlier run of the same study
/// with the same ideal-joint twin: the twin is then linked to its files (an HDF5 external link,
/// a relative symbolic link for CSV) instead of written again. Throws IoError naming
/// the file and the system's reason if a write fails; nothing is left under a final name then.
/// Files of the format not selected (a previous run's channels.csv, run.h5) are removed.
/// Returns the bytes written [B].
double WriteRunFiles(const std::string& dir, const Config& cfg, const RunResult& run,
                     const std::string& shared_twin_dir = "");

}  // namespace flexrod
