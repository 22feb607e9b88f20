// SPDX-License-Identifier: GPL-3.0-or-later
// Identities of a sweep's runs: the fingerprint of a run's resolved input and store options
// (which run a part file or a stored run is), and the key of its reduced rod (which runs share
// one rod).
#include <cstdint>
#include <cstdio>
#include <string>

#include "sweep/sweep_matrix.h"

namespace flexrod::study {

std::string Fnv1aHex(const std::string& bytes) {
  // FNV-1a, 64 bit (Fowler, Noll, Vo; offset basis and prime from the FNV reference).
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 1099511628211ull;
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

std::string RunFingerprint(const Config& cfg, const StoreOptions& store) {
  std::string text = "flexrod sweep run v1\n";
  for (const Config::Resolved& r : cfg.Resolve()) {
    if (r.key.rfind("vtk.", 0) == 0)
      continue;  // ParaView output of single runs: no effect on results
    text += r.key + "=" + r.value + " " + r.unit + (r.is_default ? "" : " set") +
            "\n";  // set vs default can differ
  }
  text += store.Describe();
  return Fnv1aHex(text);
}

std::string RodKey(const Config& cfg) {
  std::string key;
  for (const Config::Resolved& r : cfg.Resolve()) {
    if (r.key.rfind("rod.", 0) == 0 || r.key.rfind("reduction.", 0) == 0 ||
        r.key.rfind("clamp.", 0) == 0) {
      key += r.key + "=" + r.value + ";";
    }
  }
  return key;
}

}  // namespace flexrod::study
