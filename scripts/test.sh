#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite (unit, reference, slow).
# Usage: scripts/test.sh [ctest args, e.g. -L unit]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/build.sh"
build="${FLEXROD_BUILD_DIR:-$root/build}"
cd "$build"
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)" "$@"
# The parsers under libFuzzer for 60 s (scripts/fuzz.sh; longer: scripts/fuzz.sh 3600).
if [ $# -eq 0 ]; then bash "$root/scripts/fuzz.sh" 60; fi
