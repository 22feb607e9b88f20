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

}  // namespace flexrod::app
