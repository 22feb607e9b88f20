// io/run_writer.h — every file a run writes goes through one interface, a RunWriter per format,
// in this order:
//   json  resolved.toml (every input key, defaults filled in, SI, derived contact parameters as
//         notes) and summary.json (RunResult::summary); always, and first: the figures survive a
//         disk that fills up with the channels (io/run_json.cc)
//   hdf5  run.h5 (output.format hdf5, the default): the run in the layout of a run in the sweep
//         store (sweep/sweep_store.h: attributes, summary, inflection_points, poincare, spectrum,
//         channels/<name> chunked, shuffled and deflated, "unit" on every dataset), plus
//           ideal/channels/<name>  the ideal-joint twin's channels (clearance runs), or an
//                                  external link to the run.h5 that holds them
//           impacts/<column>       the impact log (mechanisms/impact_log.h ImpactColumns)
//         (io/run_h5.cc)
//   csv   channels.csv, ideal/channels.csv, impacts.csv (output.format csv; io/run_csv.cc)
//   vtk   the ParaView frames (RunResult::vtk) into the --vtk directory (io/run_vtk.h)
// A new format is a writer in a file of its own and a line in RunWriters() (io/run_writer.cc),
// plus its name among the values of output.format if the user selects it there.
// What does not live here: running (run/run.h), the sweep store (sweep/sweep_store.h).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "input/config.h"
#include "input/output_selection.h"
#include "run/run.h"
#include "signals/timeseries.h"

namespace flexrod {

/// Where a run's files go.
struct RunFileRequest {
  std::string dir;  ///< the run's output directory (--out), created if missing; "" = none (the
                    ///< json, hdf5 and csv writers then write nothing)
  /// Optional: the output directory of an earlier run of the same study with the same
  /// ideal-joint twin; the twin is then linked to its files (an HDF5 external link, a relative
  /// symbolic link for CSV) instead of written again.
  std::string shared_twin_dir;
  std::string vtk_dir;  ///< the ParaView frames' directory (--vtk), "" = none
};

/// What every writer writes from.
struct RunFileContext {
  const Config& cfg;
  const RunResult& run;
  const OutputSelection& sel;  ///< output.*
};

class RunWriter {
 public:
  virtual ~RunWriter() = default;
  /// Its name (the list at the top of this header).
  virtual const char* format() const = 0;
  /// Whether the run is written in this format (output.format, --vtk).
  virtual bool Selected(const RunFileRequest& r, const OutputSelection& sel) const = 0;
  /// Removes the files of this format that an earlier run left in r.dir: a file this run does
  /// not replace would be read as its own.
  virtual void RemoveStale(const RunFileRequest& r) const = 0;
  /// Writes its files, each whole (temporary + rename). Returns the bytes written [B]. Throws
  /// IoError naming the file and the system's reason; nothing is left under a final name then.
  virtual double Write(const RunFileRequest& r, const RunFileContext& c) const = 0;
};

/// Every writer, in the order they write.
const std::vector<std::unique_ptr<RunWriter>>& RunWriters();

/// Writes the run's files: removes every format's stale files from r.dir (if given), then each
/// selected writer writes. Returns the bytes written [B].
double WriteRun(const RunFileRequest& r, const Config& cfg, const RunResult& run);

/// The channels WriteRun reads from RunResult::channels for `cfg` (output.*, read on the first
/// call, once sim.* has been checked): the selected ones and the Poincaré channels of run.h5's
/// analysis (io/run_h5.cc). A run that only writes its files keeps these
/// (RunOutputOptions::keep_channel).
std::function<bool(const std::string&)> ChannelsTheFilesRead(const Config& cfg);

/// The selected channels (those the record has) at every stride-th sample.
study::TimeSeries SelectChannels(const study::TimeSeries& ts, const OutputSelection& sel);

/// The selected view of a record: `ts` itself when everything is selected (no copy), otherwise
/// SelectChannels into `storage`.
const study::TimeSeries& SelectedView(const study::TimeSeries& ts, const OutputSelection& sel,
                                      study::TimeSeries* storage);

/// The size of `path` if it is a regular file (not a symbolic link) [B], otherwise 0.
double RegularFileBytes(const std::string& path);

}  // namespace flexrod
