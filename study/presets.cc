// SPDX-License-Identifier: GPL-3.0-or-later
#include "study/presets.h"

namespace flexrod {

const Preset* FindPreset(const std::string& name) {
  for (const Preset& p : Presets()) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

}  // namespace flexrod
