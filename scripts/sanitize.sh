#!/usr/bin/env bash
# The whole C++ test suite under AddressSanitizer + UndefinedBehaviorSanitizer: installs what is
# missing, builds into build-asan/ (FLEXROD_ASAN_BUILD_DIR overrides it) with
# -DFLEXROD_SANITIZE=ON (RelWithDebInfo: line numbers in the reports) and runs ctest there. Any
# sanitizer report fails its test (-fno-sanitize-recover, halt_on_error). The Python module's
# pytest is left out: a sanitized extension needs the runtime preloaded into the interpreter; so
# is readme.figures: the README's figures are the Release build's to the printed digits, and its
# full-length main job under ASan outlasts the test's 900 s timeout (measured: timed out).
# Usage: scripts/sanitize.sh [ctest args, e.g. -L unit]   (about 40 min on 2 cores)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export FLEXROD_BUILD_DIR="${FLEXROD_ASAN_BUILD_DIR:-$root/build-asan}"
bash "$root/scripts/build.sh" -DFLEXROD_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DFLEXROD_BENCHMARKS=OFF
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:abort_on_error=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
cd "$FLEXROD_BUILD_DIR"
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)" -E '^(python\.|readme\.figures$)' "$@"
