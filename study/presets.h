// study/presets.h — the presets of examples/*.toml, built into the binary at configure time
// (cmake/EmbedPresets.cmake). A preset is a TOML input like any user file.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <string>
#include <vector>

namespace flexrod {

struct Preset {
  std::string name;  ///< file name without .toml, e.g. "flexible-rig"
  std::string toml;  ///< its text
};

const std::vector<Preset>& Presets();
/// The preset of that name, or nullptr.
const Preset* FindPreset(const std::string& name);

}  // namespace flexrod
