// SPDX-License-Identifier: GPL-3.0-or-later
#include "input/presets.h"

#include <filesystem>

#include "common/error.h"
#include "common/files.h"

namespace flexrod {

const Preset* FindPreset(const std::string& name) {
  for (const Preset& p : Presets()) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

const Preset* FindRunPreset(const std::string& name) {
  return name.rfind("sweep-", 0) == 0 ? nullptr : FindPreset(name);  // sweep-* are matrices
}

std::string RunPresetNames() {
  std::string names;
  for (const Preset& q : Presets()) {
    if (FindRunPreset(q.name)) names += (names.empty() ? "" : ", ") + q.name;
  }
  return names;
}

Config LoadRunInput(const std::string& input, const std::vector<std::string>& sets) {
  Config cfg;
  if (const Preset* p = FindRunPreset(input)) {
    cfg.LoadToml(p->toml, "preset " + input);
  } else if (CheckPathLength("input", input); std::filesystem::exists(input)) {
    cfg.LoadTomlFile(input);
  } else {
    throw InputError("input", input,
                     "is neither a preset (" + RunPresetNames() + ") nor an existing TOML file");
  }
  for (const std::string& s : sets) cfg.SetAssignment(s);
  return cfg;
}

}  // namespace flexrod
