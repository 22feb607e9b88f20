// input/presets.h — the presets of examples/*.toml, built into the binary at configure time
// (cmake/EmbedPresets.cmake). A preset is a TOML input like any user file; LoadRunInput reads
// a run's input (a preset or a file, then --set assignments) as `flexrod run` and the Python
// module take it.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <string>
#include <vector>

#include "input/config.h"

namespace flexrod {

struct Preset {
  std::string name;  ///< file name without .toml, e.g. "flexible-rig"
  std::string toml;  ///< its text
};

const std::vector<Preset>& Presets();
/// The preset of that name, or nullptr.
const Preset* FindPreset(const std::string& name);

/// The run input preset of that name: nullptr for a sweep-* matrix or an unknown name.
const Preset* FindRunPreset(const std::string& name);
/// The run input presets' names, comma-separated (the sweep-* matrices left out).
std::string RunPresetNames();

/// The input of one run: the preset `input` (not a sweep-* matrix) or the TOML file of that
/// path, then the "key=value" assignments in order. InputError("input", ...) if it is neither.
Config LoadRunInput(const std::string& input, const std::vector<std::string>& sets);

}  // namespace flexrod
