// sweep/sweep_store.h — the results of a sweep on disk. A finished run becomes a StoredRun:
// its resolved input, status, summary (peaks, per-revolution statistics, load amplification),
// the positive and negative turning ("inflection") points of the slider acceleration, the
// Poincaré points, the amplitude spectrum, and a selection of channels decimated to the store
// rate. Each StoredRun is written whole into a part file FILE.h5.parts/<fingerprint>.h5
// (temporary + fsync + rename: a part is complete or absent, whatever kills the process), and
// the store FILE.h5 is assembled from the parts in run-id order the same way.
//
// HDF5 layout (every dataset has an attribute "unit"; numeric attributes a sibling "<name>.unit"):
//   /                       attrs format, name, origin, base, matrix (the matrix text), axes,
//                           num_runs, num_failed
//   /runs/run_00042         attrs run_id, fingerprint, status, message, label, input_toml,
//                           summary_json, wall_time, and every resolved input key = value (+unit)
//     summary               attrs: peak_positive, ..., amplification_negative (see AnalyseRun)
//     inflection_points/{positive,negative}/{time, crank_angle, value}
//     poincare/{time, <channel>...}   attrs jitter_<channel>, jitter_normalised_<channel>
//     spectrum/{frequency, amplitude} attrs channel, window, resolution, num_samples
//     channels/<name>        chunked, deflate; attrs sample_rate, start_time, decimation
// A part file holds one run with the same layout at its root. A text attribute longer than
// 60000 bytes (HDF5 keeps attributes in a 64 KiB object header) continues in "<name>.1", ...
// What does not live here: the matrix (sweep/sweep_matrix.h), running (sweep/sweep.h),
// the comparisons (sweep/sweep_compare.h).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "common/hdf5.h"
#include "input/config.h"
#include "run/run.h"
#include "signals/timeseries.h"
#include "sweep/sweep_matrix.h"

namespace flexrod::study {

/// A stored series: name, unit, values [unit] (a channel, a column of points or of impacts).
using StoredSeries = Channel;

struct StoredScalar {
  std::string name;
  double value{0.0};  ///< [unit]; NaN when undefined (e.g. no ideal twin)
  std::string unit;
};

/// Turning points of one direction, as stored.
struct StoredPoints {
  std::vector<double> time;         ///< [s]
  std::vector<double> crank_angle;  ///< wrapped to [0, 2π) [rad]
  std::vector<double> value;        ///< slider acceleration [m/s^2]
};

struct StoredRun {
  int id{-1};                ///< run number in the matrix (set when assembled)
  std::string fingerprint;   ///< RunFingerprint
  std::string label;         ///< the run's matrix values
  std::string input_toml;    ///< the run's complete input (InputToml)
  std::string status;        ///< "completed" or the failure ("integrator-failure", "error", ...)
  std::string message;       ///< failure message (empty when completed)
  std::string summary_json;  ///< RunResult::summary (includes wall times)
  double wall_time{0.0};     ///< [s] (not part of the results: excluded from SameResults)
  std::vector<StoredScalar> summary;
  StoredPoints positive, negative;
  std::vector<StoredSeries> poincare;  ///< first "time" [s], then the Poincaré channels
  std::vector<StoredScalar> poincare_jitter;
  std::string spectrum_channel, spectrum_window;
  double spectrum_resolution{0.0};  ///< [Hz]
  double spectrum_num_samples{0.0};
  std::vector<double> frequency;  ///< [Hz]
  std::vector<double> amplitude;  ///< [unit of the spectrum channel]
  std::string amplitude_unit;
  double channel_rate{0.0};   ///< rate of the stored channels [Hz]
  double channel_start{0.0};  ///< time of their first sample [s]
  double decimation{1.0};     ///< stored every `decimation`-th sample of the run's record
  std::vector<StoredSeries> channels;

  bool ok() const { return status == "completed"; }
  /// The summary value of that name, NaN if absent.
  double Summary(const std::string& name) const;
  /// The run's resolved input.
  Config Input() const;
};

/// The complete input of a run as TOML that Config (and `flexrod run`) reads back to the same
/// input: every key the input set, as `"key" = "text as given"` ("100 rpm"); unset keys keep
/// their defaults (a default may mean "derived", so it is never written as if set).
std::string InputToml(const Config& cfg);

/// Everything a run stores, from its input and result. Analysis (turning points, Poincaré,
/// spectrum, summary) uses the full-rate record; only the stored channels are decimated.
/// Summary names: peak_positive, peak_negative, rms [m/s^2], revolutions [1],
/// positive_median/p95/max, negative_median/p95/max [m/s^2] (per revolution),
/// ideal_peak_positive, ideal_peak_negative [m/s^2], amplification_positive,
/// amplification_negative, amplification_positive_p95, amplification_negative_p95 [1],
/// amplification_bearing_force, amplification_bearing_force_p95 [1], gauge_stress_p95 [Pa] (of
/// the per-revolution peaks of the largest |gauge stress|), num_inflection_positive,
/// num_inflection_negative, num_samples [1].
/// Never throws for a failed or short run: what cannot be computed is left out.
StoredRun AnalyseRun(const Config& cfg, const RunResult& run, const StoreOptions& store);

/// A failed run that produced no result at all (exception before or inside the solver).
StoredRun FailedRun(const Config& cfg, const StoreOptions& store, const std::string& status,
                    const std::string& message);

/// Writes a run into an (empty) group or file root / reads it back. `with_channels` = false
/// leaves out the group "channels" (the caller writes it with WriteChannels).
void WriteStoredRun(const h5::Node& group, const StoredRun& run, bool with_channels = true);
/// A channels group: attributes sample_rate [Hz], start_time [s], decimation [1], and one
/// chunked, shuffled, deflated dataset per channel (attribute "unit"), in order.
void WriteChannels(const h5::Node& group, double rate, double start, double decimation,
                   const std::vector<StoredSeries>& channels);
/// `with_channels` = false skips the channel datasets (comparisons need only the points).
StoredRun ReadStoredRun(const h5::Node& group, bool with_channels = true);

/// Part files. WritePartFile writes `path` whole: temporary, checked close, fsync, rename,
/// fsync of the directory (IoError naming the file otherwise, the temporary removed).
/// ReadPartFile throws IoError if the file is not a complete part.
void WritePartFile(const std::string& path, const StoredRun& run);
StoredRun ReadPartFile(const std::string& path, bool with_channels = true);
std::string ReadFileBytes(const std::string& path);

/// The sweep store: writes FILE.h5 whole (temporary + fsync + rename) from runs delivered in
/// id order by `next` (returns false when done).
struct StoreHeader {
  std::string name, origin, base, matrix_source;
  std::vector<std::string> axis_keys;
  int num_runs{0};
};
void WriteStore(const std::string& path, const StoreHeader& header,
                const std::function<bool(StoredRun*)>& next);

struct SweepStore {
  StoreHeader header;
  int num_failed{0};
  std::vector<StoredRun> runs;  ///< in id order
};
/// Reads a store (InputError if the file is not a flexrod sweep store).
SweepStore ReadStore(const std::string& path, bool with_channels = true);

/// The runs of an existing store, found by fingerprint, so that running a sweep again reuses
/// them. An absent or unreadable store is an empty index.
class StoreIndex {
 public:
  explicit StoreIndex(const std::string& path);
  /// True if `path` is a readable flexrod sweep store.
  static bool IsStore(const std::string& path);
  bool Has(const std::string& fingerprint) const { return groups_.count(fingerprint) > 0; }
  std::size_t size() const { return groups_.size(); }
  /// The complete run (with channels); IoError if it cannot be read.
  StoredRun Read(const std::string& fingerprint) const;

 private:
  std::string path_;
  std::map<std::string, std::string> groups_;  ///< fingerprint -> group name
};

/// True if a and b hold the same results bit for bit (every dataset and summary value, inputs,
/// status); timings are ignored. *why names the first difference.
bool SameResults(const StoredRun& a, const StoredRun& b, std::string* why = nullptr);

/// Group name of run `id` in the store: "run_00042".
std::string RunGroupName(int id);

}  // namespace flexrod::study
