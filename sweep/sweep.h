// sweep/sweep.h — running a sweep on the cores of one machine, and the pieces the MPI driver
// (app/sweep_mpi.cc) reuses: the shared reduced-rod cache, the up-front validation, one run
// computed into a StoredRun, and the session that owns the store's files (lock, finished
// runs, part files, assembly). Runs are deterministic and the store is assembled in run-id
// order, so the store does not depend on the number of threads or ranks. A sweep killed at
// any instant loses no finished run: each is a part file committed by rename, and a new
// session skips every run whose part (or whose entry in an existing store) has its
// fingerprint. What does not live here: the matrix (sweep/sweep_matrix.h), the file layout
// (sweep/sweep_store.h), progress display and MPI (app/).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/once_cache.h"
#include "fem/reduced_rod.h"
#include "run/run.h"
#include "sweep/sweep_matrix.h"
#include "sweep/sweep_store.h"

namespace flexrod::study {

/// Reduced rods shared by the runs of a sweep, keyed by RodKey: the first run that needs a rod
/// builds it, others asking meanwhile wait for it; afterwards every run shares the immutable
/// rod. Thread-safe. A rigid rod is a null pointer.
class RodCache {
 public:
  /// Rethrows the exception of a failed build to every caller of that key.
  std::shared_ptr<const fem::ReducedRod> Get(const Config& cfg);
  int num_built() const;  ///< rods built so far (distinct keys)

 private:
  OnceCache<std::shared_ptr<const fem::ReducedRod>> rods_;
};

/// Checks a sweep before anything is written. Every run's rod and mechanism are built and its
/// inputs checked (CheckRunInput, the output.* selection against its channels): an InputError
/// propagates; a numerical failure of a rod is left for its runs to record. Every store channel
/// must be a channel of some run (InputError("store.channels", name, "... available: ...")).
void ValidateSweep(const SweepMatrix& matrix, RodCache* rods);

/// Computes run `id` into what the store keeps, sharing rods and ideal-joint twins with the
/// other runs through the caches (`twins` may be null: every clearance run computes its twin).
/// An integrator failure, a NumericalError or an input rejected inside the solver become a
/// failed run with its message; any other exception (a logic error, out of memory) propagates.
/// Once `stop` (polled by the integrator) reads true, it throws Interrupted and the run has no
/// result.
StoredRun ComputeSweepRun(const SweepMatrix& matrix, int id, RodCache* rods, TwinCache* twins,
                          const std::atomic<bool>* stop = nullptr);

/// `ids` in the order to compute them on `jobs` threads so that a TwinCache of `jobs` twins
/// computes each ideal-joint twin once and no thread waits for another's twin: runs that share
/// a twin (TwinKey of their case's member 0: they differ only in joint.* keys or are members of
/// one ensemble) form groups, in the order of their first
/// run; blocks of `jobs` groups are taken in turn, one run of each group of the block at a time
/// (so the runs computed at the same moment have different twins). With one job, each group's
/// runs are adjacent. The store does not depend on the order (it is assembled in run-id order).
std::vector<int> TwinOrder(const SweepMatrix& matrix, const std::vector<int>& ids, int jobs);

/// Runs work(id) on `jobs` threads for every id next() hands out (nullopt: done). The first
/// exception thrown by work stops the hand-out and is rethrown after every thread has joined.
void RunOnThreads(int jobs, const std::function<std::optional<int>()>& next,
                  const std::function<void(int)>& work);

/// The files of a sweep store FILE.h5: parts in FILE.h5.parts/<fingerprint>.h5, the lock
/// FILE.h5.parts/.lock.
class SweepSession {
 public:
  /// Creates FILE.h5.parts/, takes its lock (InputError if another sweep holds it), removes
  /// temporaries left by a killed sweep and finds the finished runs: a part whose fingerprint
  /// and resolved input match, or a run of an existing FILE.h5 with the same fingerprint.
  SweepSession(const SweepMatrix& matrix, const std::string& store_path);
  ~SweepSession();
  SweepSession(const SweepSession&) = delete;
  SweepSession& operator=(const SweepSession&) = delete;

  const std::string& store_path() const { return store_path_; }
  const std::string& parts_dir() const { return parts_dir_; }
  /// Runs without a finished result, ascending ids.
  const std::vector<int>& pending() const { return pending_; }
  int num_from_parts() const { return from_parts_; }  ///< finished runs found as parts
  int num_from_store() const { return from_store_; }  ///< finished runs found in FILE.h5
  std::string PartPath(int id) const;

  /// Commits a finished run as its part file. Thread-safe.
  void Save(const StoredRun& run);
  /// Commits a part file received as bytes (MPI); checks it reads back as run `id` and
  /// returns it (without channels).
  StoredRun SaveBytes(int id, const std::string& bytes);

  struct Outcome {
    int num_runs{0};
    int num_failed{0};
    std::string store_path;
  };
  /// Writes FILE.h5 (temporary + rename) from the parts and the previous store, in run-id
  /// order; removes the parts directory afterwards unless keep_parts (and only after the store is
  /// written, closed, read back complete and renamed). IoError if a run has no result or the
  /// store cannot be written; the parts are then kept, so that a rerun resumes from them.
  Outcome Assemble(bool keep_parts);

 private:
  const SweepMatrix& matrix_;
  std::string store_path_, parts_dir_;
  std::vector<std::string> fingerprints_;
  std::vector<int> pending_;
  int from_parts_{0}, from_store_{0};
  int lock_fd_{-1};
};

/// What happens during a sweep, for progress display.
struct SweepEvent {
  enum class Kind { kStart, kRunDone };
  Kind kind{Kind::kStart};
  int total{0};             ///< runs in the matrix
  int already_done{0};      ///< finished before this session
  int to_run{0};            ///< runs this session computes
  int done{0};              ///< computed so far in this session
  int failed{0};            ///< of those, failed
  int id{-1};               ///< kRunDone: the run
  bool ok{true};            ///< kRunDone: completed?
  std::string label;        ///< kRunDone: its matrix values
  std::string message;      ///< kRunDone: failure message
  double run_seconds{0.0};  ///< kRunDone: its wall time [s]
};

struct SweepOptions {
  int jobs{1};             ///< worker threads, >= 1
  bool keep_parts{false};  ///< keep FILE.h5.parts/ after assembly
  /// Called for every event, serialised (never concurrently).
  std::function<void(const SweepEvent&)> on_event;
  /// Polled by every run's integrator: once true, the runs in progress stop, RunSweep throws
  /// Interrupted, and the finished runs stay as parts (the next session resumes). nullptr:
  /// never stops.
  const std::atomic<bool>* stop{nullptr};
};

/// InputError(key, path, ...) unless the store path ends in .h5.
void CheckStorePath(const std::string& key, const std::string& path);

/// A whole sweep on this machine: validate, open the session, run the pending runs on
/// options.jobs threads, assemble the store.
SweepSession::Outcome RunSweep(const SweepMatrix& matrix, const std::string& store_path,
                               const SweepOptions& options);

}  // namespace flexrod::study
