// app/sweep_app.h — the `flexrod sweep` command's pieces shared by its two drivers: the
// request (flags), the progress display (a bar with runs done, failures and ETA on a
// terminal, plain log lines otherwise) and the work after the store is written (summary CSV,
// amplification plot). The local driver is in app/cmd_sweep.cc, the MPI driver in
// app/sweep_mpi.cc. What does not live here: the sweep itself (sweep/sweep.h).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "sweep/sweep.h"

namespace flexrod::app {

struct SweepRequest {
  std::string matrix{study::kDefaultSweepMatrix};  ///< built-in matrix name or file
  std::vector<std::string> sets;                   ///< --set key=value (store.* included)
  std::string out;                                 ///< --out FILE.h5; empty: out/<name>.h5
  int jobs{0};                                     ///< threads (per rank); 0: all cores
  bool keep_parts{false};
  bool list{false};
  bool no_plot{false};
};

/// The matrix of the request, with --set applied.
study::SweepMatrix LoadRequestMatrix(const SweepRequest& request);
/// --out or out/<matrix name>.h5.
std::string StorePath(const SweepRequest& request, const study::SweepMatrix& matrix);

/// Prints sweep events to stderr: a redrawn bar on a terminal, one line per run otherwise.
class ProgressDisplay {
 public:
  ProgressDisplay(std::string name, std::string workers);
  void operator()(const study::SweepEvent& event);
  /// Ends the bar and prints where the store is.
  void Finish(const study::SweepSession::Outcome& outcome);

 private:
  std::string name_, workers_;
  bool tty_{false};
  std::chrono::steady_clock::time_point start_;
  study::SweepEvent last_;
};

/// After the store is written: FILE.summary.csv and (unless no_plot) FILE.amplification.png.
void AfterSweep(const SweepRequest& request, const std::string& store_path);

/// True if this process was started by Open MPI's mpirun (OMPI_COMM_WORLD_SIZE is set).
bool LaunchedUnderMpi();
/// The sweep across the ranks of MPI_COMM_WORLD; every rank calls it. Returns the exit code.
int RunSweepMpi(const SweepRequest& request);

}  // namespace flexrod::app
