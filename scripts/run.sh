#!/usr/bin/env bash
# Installs what is missing, builds, and runs the main job on the built-in default study.
# Extra arguments are passed to `flexrod run` (e.g. --set drive.speed="250 rpm").
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/build.sh"
build="${FLEXROD_BUILD_DIR:-$root/build}"
"$build/flexrod" run "$@"
