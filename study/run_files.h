// study/run_files.h — the files a run writes into its output directory:
//   resolved.toml  every input key, defaults filled in, SI, derived contact parameters as notes
//   summary.json   RunResult::summary
//   run.h5         (output.format hdf5, the default) the run in the layout of a run in the sweep
//                  store (study/sweep_store.h: attributes, summary, inflection_points, poincare,
//                  spectrum, channels/<name> chunked, shuffled and deflated, "unit" on every
//                  dataset), plus
//                    ideal/channels/<name>  the ideal-joint twin's channels (clearance runs), or
//                                           an external link to the run.h5 that holds them
//                    impacts/<column>       the impact log (study/impact_log.h ImpactColumns)
//   channels.csv, ideal/channels.csv, impacts.csv   (output.format csv)
// What does not live here: running (study/run.h), the sweep store (study/sweep_store.h).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "study/config.h"
#include "study/run.h"
#include "study/timeseries.h"

namespace flexrod {

/// What a run's channel files hold: output.channels (the standard set, all, or a list) every
/// `stride`-th sample (output.rate), in the formats of output.format.
struct OutputSelection {
  bool standard{true};                ///< the standard set (IsStandardChannel)
  std::vector<std::string> channels;  ///< the list; empty and not standard = all
  std::size_t stride{1};
  bool hdf5{true};
  bool csv{false};
};

/// output.channels = standard: what the rig measures or a user plots (crank, slider, rod
/// angle, bearing force, journal centre, contact forces, rod deflection, gauge strains), not
/// what the others derive or only a developer reads (force components, stresses = E strain,
/// penetration, modal coordinates, energies, constraint violation: the summary has those).
bool IsStandardChannel(const std::string& name);

/// Reads and checks the output.* keys for a record at `sample_rate` [Hz]. `available` (if
/// given) are the run's channel names, checked against the selection. Throws InputError
/// naming the key, the value and the rule.
OutputSelection ReadOutputSelection(const Config& cfg, double sample_rate,
                                    const std::vector<std::string>* available);

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
