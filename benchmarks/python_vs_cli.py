#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Solver wall of one run from Python (flexrod.run) against the same run from the CLI
(`flexrod run`): alternating runs, the minimum of each, and their ratio (the issue's budget:
Python at most 5 % over the CLI). The solver wall is the integrator's wall time of the run
(summary "integrator" "wall_time [s]"), so file output and plots do not count.

    PYTHONPATH=build/python /usr/bin/python3 benchmarks/python_vs_cli.py [--rounds 5]
        [--binary build/flexrod] [--set key=value ...]

Default case: the main job (flexible rig, 1 s settling + 3 s capture at 100 kHz), with the
CLI's channel file cut to two channels at 1 kHz (the run records and analyses every channel
at the full rate either way). A measurement, never a test.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile

import flexrod

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("--binary", default=os.path.join(ROOT, "build", "flexrod"))
    p.add_argument("--input", default="flexible-rig")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    args = p.parse_args(argv)
    sets = {"output.channels": "crank_angle,slider_acceleration", "output.rate": "1 kHz"}
    sets.update(dict(s.split("=", 1) for s in args.set))

    cli_walls, py_walls = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for i in range(args.rounds):
            out = os.path.join(tmp, f"cli{i}")
            cmd = [args.binary, "run", args.input, "--no-plot", "--out", out]
            for k, v in sets.items():
                cmd += ["--set", f"{k}={v}"]
            subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
            with open(os.path.join(out, "summary.json")) as f:
                cli_walls.append(json.load(f)["integrator"]["wall_time [s]"])
            r = flexrod.run(args.input, set=sets)
            py_walls.append(r.summary["integrator"]["wall_time [s]"])
            print(f"round {i + 1}: CLI {cli_walls[-1]:.3f} s, Python {py_walls[-1]:.3f} s",
                  flush=True)
    cli, py = min(cli_walls), min(py_walls)
    print(f"solver wall, min of {args.rounds}: CLI {cli:.3f} s, Python {py:.3f} s, "
          f"ratio Python/CLI {py / cli:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
