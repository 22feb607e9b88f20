// input/output_selection.h — the output.* keys of a run, read and checked once: which channels
// its files hold, at which rate, in which formats. The files themselves: io/run_writer.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "input/config.h"

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

/// Whether the selection writes the channel `name` (standard set, list, or all).
bool Selects(const OutputSelection& sel, const std::string& name);

/// Reads and checks the output.* keys for a record at `sample_rate` [Hz]. `available` (if
/// given) are the run's channel names, checked against the selection. Throws InputError
/// naming the key, the value and the rule.
OutputSelection ReadOutputSelection(const Config& cfg, double sample_rate,
                                    const std::vector<std::string>* available);

}  // namespace flexrod
