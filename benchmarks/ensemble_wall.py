#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The main job with its default ensemble against one run (issue 56, "Speed").

  benchmarks/ensemble_wall.py [--rounds N] [--binary build/flexrod] [--members 1,3,4] [--table2]

Times `flexrod run --no-plot` on the built-in default study (the main job) in a fresh process,
N rounds each (default 3), and prints the wall time (minimum over the rounds), the CPU time and
the ratio to the single run:
- "single run (before)": one member with the fixed settle (`--ensemble 1 --set
  sim.steady_window=false`), what `flexrod run` computed before ensembles;
- "single run, steady window": one member, settling until its window is stationary;
- the default ensemble (`flexrod run` with no flag), and `--ensemble M` for each M asked.
With --table2, also the whole of RIG.md Table 2 (`flexrod sweep --no-plot`, once each: about 2
and 8 minutes on two cores): its 189 cases as single runs (fixed settle, as before ensembles)
and as 4-member ensembles (756 runs), with their ratio.
Timing only: never a test.
"""
import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def timed(command):
    """(wall [s], CPU of the child [s]) of one run of `command`."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--binary", default=os.path.join(HERE, "..", "build", "flexrod"))
    p.add_argument("--members", default="4", help="extra ensemble sizes, comma-separated")
    p.add_argument("--table2", action="store_true", help="also time the Table 2 sweeps")
    args = p.parse_args()
    cases = [("single run (before)", ["--ensemble", "1", "--set", "sim.steady_window=false"]),
             ("single run, steady window", ["--ensemble", "1"]),
             ("default ensemble (3 members)", [])]
    for m in [int(x) for x in args.members.split(",") if x]:
        cases.append(("ensemble of %d" % m, ["--ensemble", str(m)]))
    with tempfile.TemporaryDirectory() as tmp:
        results = []
        for name, extra in cases:
            walls, cpus = [], []
            for _ in range(args.rounds):
                w, c = timed([args.binary, "run", "--no-plot", "--out",
                              os.path.join(tmp, "run")] + extra)
                walls.append(w)
                cpus.append(c)
            results.append((name, min(walls), min(cpus)))
    base = results[0][1]
    print("main job (flexrod run --no-plot), %d rounds, minimum:" % args.rounds)
    for name, wall, cpu in results:
        print("  %-32s wall %6.2f s  CPU %6.2f s  wall / single run %.2f" %
              (name, wall, cpu, wall / base))
    if args.table2:
        with tempfile.TemporaryDirectory() as tmp:
            sweeps = []
            for name, extra in (("Table 2, single runs (before)",
                                 ["--set", "sim.steady_window=false"]),
                                ("Table 2, 4-member ensembles", ["--set", "ensemble.members=4"])):
                w, c = timed([args.binary, "sweep", "--no-plot", "--out",
                              os.path.join(tmp, "t2.h5")] + extra)
                os.remove(os.path.join(tmp, "t2.h5"))
                sweeps.append((name, w, c))
        print("RIG.md Table 2 (flexrod sweep --no-plot), once each:")
        for name, wall, cpu in sweeps:
            print("  %-32s wall %7.1f s  CPU %7.1f s  wall / single runs %.2f" %
                  (name, wall, cpu, wall / sweeps[0][1]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
