// app/plotting.h — PNG plots through Debian's matplotlib: the program writes CSV/JSON, then
// runs scripts/flexrod_plots.py with /usr/bin/python3 (not the python3 first on PATH, which may
// lack matplotlib). A missing matplotlib is a warning, never a failure of the run.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <string>
#include <vector>

namespace flexrod::app {

/// Runs `flexrod_plots.py <args...>`; returns true on success, prints a warning otherwise.
bool RunPlotScript(const std::vector<std::string>& args);
/// Slider acceleration against crank angle (and ideal twin when present) for a run directory.
bool PlotRun(const std::string& dir);

/// The plots of a run directory by a plot process started before the run: its imports
/// (numpy, matplotlib, h5py: about a second) overlap the simulation on another core. Finish()
/// lets it plot the files written meanwhile; destroying it unfinished stops it without plots.
class RunPlotter {
 public:
  explicit RunPlotter(const std::string& dir);
  ~RunPlotter();
  RunPlotter(const RunPlotter&) = delete;
  RunPlotter& operator=(const RunPlotter&) = delete;
  /// Plots now and waits; true on success (a warning is printed otherwise).
  bool Finish();

 private:
  std::string dir_;
  int pid_{-1};
  int to_child_{-1};     ///< write end of the child's stdin
  bool Stop(bool plot);  ///< plot: "go" and wait; else kill it
};

}  // namespace flexrod::app
