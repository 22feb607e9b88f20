#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The exact rod with its default (modal, co-rotated) damping against Kelvin-Voigt damping
(issue 57, "Speed": at most 25 % slower).

  benchmarks/exact_rod_damping.py [--rounds N] [--binary build/flexrod]

Times `flexrod run --no-plot --ensemble 1 --set rod.type=exact` on the main job in a fresh
process, N rounds each (default 3), and prints the wall and CPU time (minimum over the rounds),
the integrator's steps and the ratio to Kelvin-Voigt:
- "Kelvin-Voigt": damping.type = rayleigh with beta = 6.29e-5 s, the Kelvin-Voigt damping the
  exact rod had before (fitted to 1 % on its first mechanism mode, 50.6 Hz);
- "modal (band)": the default, damping.type = band, realised as co-rotated modal damping
  (multibody/corotated_damping.h).
Timing only: never a test.
"""
import argparse
import json
import os
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from ensemble_wall import timed  # noqa: E402  (wall and CPU of one child process)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--binary", default=os.path.join(HERE, "..", "build", "flexrod"))
    args = ap.parse_args()
    cases = [("Kelvin-Voigt", ["--set", "damping.type=rayleigh", "--set", "damping.beta=6.29e-5 s"]),
             ("modal (band)", [])]
    results = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, extra in cases:
            out = os.path.join(tmp, name.split()[0])
            cmd = [args.binary, "run", "--no-plot", "--ensemble", "1", "--set", "rod.type=exact",
                   "--out", out] + extra
            times = [timed(cmd) for _ in range(args.rounds)]
            with open(os.path.join(out, "summary.json")) as f:
                s = json.load(f)
            steps = s["integrator"]["steps"]
            results.append((name, min(t[0] for t in times), min(t[1] for t in times), steps))
    base = results[0]
    print(f"{'damping':<16}{'wall [s]':>10}{'CPU [s]':>10}{'steps':>10}{'wall ratio':>12}")
    for name, wall, cpu, steps in results:
        print(f"{name:<16}{wall:>10.2f}{cpu:>10.2f}{steps:>10}{wall / base[1]:>12.2f}")


if __name__ == "__main__":
    main()
