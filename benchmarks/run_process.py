#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The whole `flexrod run` process against its solver (issue 24: files and plots within 1.5x
the solver wall time, output under 60 MB).

  benchmarks/run_process.py [--rounds N] [--binary build/flexrod] [-- flexrod run args...]

Runs `flexrod run ARGS --out TMP` N times (default 5, the main job) and prints, per round and
as the minimum over the rounds: the process wall time, the solver wall time (the run's and its
ideal twin's integrator wall, from summary.json), their ratio, the time the files took (the
report's "files:" line), and the bytes written. Timing only: never a test.
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("--binary", default=os.path.join(os.path.dirname(__file__), "..", "build",
                                                    "flexrod"))
    p.add_argument("extra", nargs="*", help="flexrod run arguments, after --")
    args = p.parse_args(argv)
    rounds, binary, extra = args.rounds, args.binary, args.extra
    rows = []
    for r in range(rounds):
        out = tempfile.mkdtemp(prefix="flexrod_bench_run_")
        t0 = time.perf_counter()
        proc = subprocess.run([binary, "run", *extra, "--out", out], capture_output=True, text=True)
        wall = time.perf_counter() - t0
        if proc.returncode != 0:
            print(proc.stderr, file=sys.stderr)
            return 1
        with open(os.path.join(out, "summary.json")) as f:
            s = json.load(f)
        solver = s["integrator"]["wall_time [s]"]
        if "ideal" in s and "integrator" in s["ideal"]:
            solver += s["ideal"]["integrator"]["wall_time [s]"]
        m = re.search(r"files: ([0-9.e+]+) MB in ([0-9.]+) s", proc.stdout)
        files = float(m.group(2)) if m else float("nan")
        size = sum(os.path.getsize(os.path.join(d, f)) for d, _, fs in os.walk(out) for f in fs)
        rows.append((wall, solver, files, size))
        print("round %d: process %.3f s, solver %.3f s, ratio %.2f, files %.2f s, output %.1f MB"
              % (r + 1, wall, solver, wall / solver, files, size / 1e6))
        shutil.rmtree(out)
    best = min(rows, key=lambda x: x[0] / x[1])
    print("best ratio: process %.3f s / solver %.3f s = %.2f (files %.2f s, output %.1f MB)"
          % (best[0], best[1], best[0] / best[1], best[2], best[3] / 1e6))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
