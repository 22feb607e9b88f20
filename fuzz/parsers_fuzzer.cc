// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target for the input parsers (issue 25): the first byte picks the parser, the rest
// is its text.
//   0: an input file (Config::LoadToml)     1: a sweep matrix (ParseSweepMatrix)
//   2: --set assignments, one per line (Config::SetAssignment), then Config::Resolve
// Bad input must end in InputError (a message naming key, value and rule); anything else — a
// crash, a sanitizer report, another exception, a hang — is a finding. Built and run by
// scripts/fuzz.sh (Debian's clang with -fsanitize=fuzzer,address,undefined).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <sstream>
#include <string>

#include "common/error.h"
#include "input/config.h"
#include "sweep/sweep_matrix.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    switch (data[0] % 3) {
      case 0: {
        flexrod::Config cfg;
        cfg.LoadToml(text, "fuzz");
        (void)cfg.Resolve();
        break;
      }
      case 1:
        (void)flexrod::study::ParseSweepMatrix(text, "fuzz", "/nonexistent");
        break;
      default: {
        flexrod::Config cfg;
        std::istringstream lines(text);
        for (std::string line; std::getline(lines, line);) cfg.SetAssignment(line);
        (void)cfg.Resolve();
        break;
      }
    }
  } catch (const flexrod::InputError&) {
    // the expected outcome of bad input
  }
  return 0;  // any other exception escapes: libFuzzer reports it as a crash with its input
}
