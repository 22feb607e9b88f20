// SPDX-License-Identifier: GPL-3.0-or-later
#include "study/presets.h"

#include <filesystem>

#include "common/error.h"

namespace flexrod {

const Preset* FindPreset(const std::string& name) {
  for (const Preset& p : Presets()) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

Config LoadRunInput(const std::string& input, const std::vector<std::string>& sets) {
  Config cfg;
  const Preset* p =
      input.rfind("sweep-", 0) == 0 ? nullptr : FindPreset(input);  // sweep-* are matrices
  if (p) {
    cfg.LoadToml(p->toml, "preset " + input);
  } else if (std::filesystem::exists(input)) {
    cfg.LoadTomlFile(input);
  } else {
    std::string names;
    for (const Preset& q : Presets()) {
      if (q.name.rfind("sweep-", 0) != 0) names += (names.empty() ? "" : ", ") + q.name;
    }
    throw InputError("input", input,
                     "is neither a preset (" + names + ") nor an existing TOML file");
  }
  for (const std::string& s : sets) cfg.SetAssignment(s);
  return cfg;
}

}  // namespace flexrod
