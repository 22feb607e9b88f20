// mechanisms/modal_analysis.h — `flexrod modes` and flexrod.modes() in Python: the modal analysis
// of one rod from its rod.*, reduction.* and modes.* keys (full FE against the reduced model,
// per mode), the flags that set those keys, and the JSON of the result. What does not live
// here: the reduction itself (fem/reduced_rod.h), printing (app/cmd_modes.cc).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "fem/reduced_rod.h"
#include "input/config.h"

namespace flexrod {

/// A flag of `flexrod modes` (a keyword argument of flexrod.modes() without the dashes) and
/// the input key it sets.
struct ModesFlag {
  const char* name;  ///< "--height"
  const char* key;   ///< "rod.height"
  const char* help;  ///< with the unit, e.g. "bar height, e.g. \"19.05 mm\""
};
const std::vector<ModesFlag>& ModesFlags();

struct ModalAnalysis {
  fem::RodSpec rod;
  fem::ReductionSpec spec;
  int num_coordinates{0};                ///< of the reduced rod
  std::vector<fem::ModeReportRow> rows;  ///< per mode: frequencies [Hz], error, MAC, mass [kg]
  std::string warning;                   ///< the mesh's precision warning, "" if none
  /// The run's rod in its assembled mechanism (mechanism.type with an ideal small-end joint, crank
  /// held at angle 0: the modes damping.type = ratio | band | material refers to,
  /// mechanisms/mechanism_damping.h), and the ratio each gets; empty for a rigid rod or
  /// damping.type = rayleigh | none.
  Vec mechanism_hz;      ///< [Hz], ascending
  Vec mechanism_ratios;  ///< ζ [-]
};

/// The analysis of `cfg`'s rod (InputError for bad keys, before any work).
ModalAnalysis AnalyseModes(const Config& cfg);

/// {"inputs": the rod.*, reduction.*, modes.*, damping.* keys with value and unit,
/// "num_coordinates", "units", "modes": [{mode, full_hz, reduced_hz, rel_error, mac,
/// effective_mass, rigid_body}], "mechanism_modes": [{mode, frequency_hz, damping_ratio}]};
/// non-finite numbers are null. `flexrod modes --json` writes it.
nlohmann::json ModesJson(const Config& cfg, const ModalAnalysis& analysis);

}  // namespace flexrod
