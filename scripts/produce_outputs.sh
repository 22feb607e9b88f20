#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Runs a fixed set of short cases with one flexrod binary into DIR, for a before/after
# comparison of a restructuring (scripts/compare_outputs.py DIR_A DIR_B must find no
# difference but wall and CPU times). About 2 minutes on 2 cores.
# Usage: scripts/produce_outputs.sh BINARY DIR
set -euo pipefail
bin="$(realpath "$1")"
out="$2"
rm -rf "$out"
mkdir -p "$out"
run() {  # name, then the arguments of flexrod
  local name="$1"; shift
  "$bin" "$@" --out "$out/$name" > "$out/$name.stdout" 2>&1
}
short=(--set sim.settle=0.05 --set sim.capture=0.3 --set sim.start=rigid)
run main run --no-plot "${short[@]}"
run main-csv run --no-plot "${short[@]}" --set output.format=csv
run pendulum run flexible-pendulum --no-plot --set sim.capture=0.2 --vtk "$out/pendulum-vtk"
run pendulum-static run flexible-pendulum --no-plot --set sim.capture=0.1 --set sim.start=static
run rigid run rigid-rig --no-plot --set sim.capture=1
run simeon run simeon-crank --no-plot
run simeon-steady run simeon-crank --no-plot --set sim.start=steady --set damping.type=ratio \
  --set damping.ratio=0.02
run exact run --no-plot --set rod.type=exact --set sim.settle=0.05 --set sim.capture=0.05 \
  --set sim.start=rigid --vtk "$out/exact-vtk"
"$bin" sweep sweep-small --no-plot --jobs 1 --out "$out/sweep-small.h5" > "$out/sweep.stdout" 2>&1
