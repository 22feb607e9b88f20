#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""flexrod against Exudyn 1.11 on the same flexible slider-crank (issue 24, "Speed").

  benchmarks/exudyn_match.py [--rounds N] [--binary build/flexrod] [--input FILE] [-- extra --set args]

Runs `flexrod run` on benchmarks/exudyn-match.toml (a copy of ../shared/bench/) twice: the ideal joint (the file's
header: joint.type=ideal, sim.sample_rate=10 kHz) and the 0.5 mm clearance joint (its ideal
twin included, as a clearance run computes it). Each case runs N times (default 3) in a fresh
process; per case it prints the process CPU time (user + system, every thread: the twin runs
on a second core when there is one), the minimum over the rounds, the ratio to Exudyn's CPU
time on this machine class, and the run's steps, residuals, Jacobians, events and, from one more
run with `--profile` (not timed: its clock reads cost a few percent), the shares of the solver
wall spent in residuals, Jacobians, linear solves, output and the rest, the unknowns whose
local error estimate set the step, and the share of the steps at each BDF order. It also times
the process start-up alone (`flexrod --help`, minimum over at least 5 rounds), which every run
pays: the dynamic loader maps and relocates the shared libraries. Timing only: never a test.

Exudyn's CPU times are the ones the input file's header quotes (Exudyn 1.11, fixed-step
generalised-alpha, 10 Craig-Bampton modes of a 2565-dof solid rod, one core): ideal joint
7.4 s (h = 1e-4 s), clearance 95 s (h = 1e-5 s), 3 s simulated each.
"""
import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
EXUDYN_CPU = {"ideal": 7.4, "clearance": 95.0}  # [s] ../shared/bench/exudyn-match.toml header
CASES = {
    "ideal": ["--set", "joint.type=ideal", "--set", "sim.sample_rate=10 kHz"],
    "clearance": [],
}


def child_cpu(command):
    """Runs `command` to its end: (its completed process, its CPU seconds, user + system, every
    thread)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = subprocess.run(command, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return proc, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def run_once(binary, toml, args):
    """One run in a fresh process: (CPU seconds of the child, summary)."""
    out = tempfile.mkdtemp(prefix="flexrod_exudyn_match_")
    try:
        proc, cpu = child_cpu([binary, "run", toml, "--no-plot", "--out", out, *args])
        if proc.returncode != 0:
            sys.stderr.write(proc.stderr)
            raise SystemExit(1)
        with open(os.path.join(out, "summary.json")) as f:
            return cpu, json.load(f)
    finally:
        shutil.rmtree(out, ignore_errors=True)


def startup_cpu(binary, rounds):
    """CPU seconds of `flexrod --help`, minimum over the rounds: the process start-up every run
    pays (the dynamic loader mapping and relocating the shared libraries, HDF5's among them)."""
    return min(child_cpu([binary, "--help"])[1] for _ in range(max(rounds, 5)))


def describe(name, s):
    it = s["integrator"]
    wall = s["wall_time [s]"]
    line = ("    %-5s solver wall %.3f s: %d steps, %d residuals, %d Jacobians (%d matrix set-ups), "
            "%d events, %d error-test / %d convergence failures; output (sampling) %.0f %% of the wall"
            % (name, wall, it["steps"], it["residual_evaluations"], it["jacobian_evaluations"],
               it["matrix_setups"], it["roots_found"], it["error_test_failures"], it["nonlinear_convergence_failures"],
               100.0 * it["output_time [s]"] / wall if wall > 0 else 0.0))
    print(line)


def describe_shares(s):
    """The profiled run's shares of its solver wall (summary integrator, `flexrod run --profile`)."""
    it = s["integrator"]
    wall = it["wall_time [s]"]
    parts = [("residuals", it["residual_time [s]"]), ("Jacobians", it["jacobian_time [s]"]),
             ("linear solves", it["linear_solve_time [s]"]), ("output", it["output_time [s]"])]
    rest = wall - sum(t for _, t in parts)
    print("    run   solver wall shares (one more run, --profile): "
          + ", ".join("%s %.0f %%" % (name, 100.0 * t / wall) for name, t in parts)
          + ", the rest (IDA, events, step bookkeeping) %.0f %%" % (100.0 * rest / wall))
    limiting = it.get("step_limiting_unknowns", [])
    if limiting and it["steps"] > 0:
        print("    run   step set by (largest weighted local error after a step): "
              + ", ".join("%s %.0f %%" % (u["unknown"], 100.0 * u["steps"] / it["steps"])
                          for u in limiting[:4]))
    by_order = it.get("steps_by_order", {})
    if by_order and it["steps"] > 0:
        print("    run   steps by BDF order: "
              + ", ".join("%s: %.0f %%" % (k, 100.0 * n / it["steps"]) for k, n in by_order.items()))


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--binary", default=os.path.join(HERE, "..", "build", "flexrod"))
    # a copy of ../shared/bench/exudyn-match.toml
    p.add_argument("--input", default=os.path.join(HERE, "exudyn-match.toml"))
    p.add_argument("extra", nargs="*", help="further flexrod run arguments, after --")
    args = p.parse_args(argv)
    rounds, binary, toml, extra = args.rounds, args.binary, args.input, args.extra
    if rounds < 1 or not os.path.isfile(toml):
        print(__doc__, file=sys.stderr)
        return 2
    startup = startup_cpu(binary, rounds)
    libraries = subprocess.run(["ldd", binary], capture_output=True, text=True).stdout.count("=>")
    print("process start-up (flexrod --help, %d shared libraries): CPU min %.3f s" % (libraries, startup))
    for case, args in CASES.items():
        cpus, summary = [], None
        for _ in range(rounds):
            cpu, summary = run_once(binary, toml, args + extra)
            cpus.append(cpu)
        best = min(cpus)
        print("%s: flexrod CPU min %.3f s over %d runs (%s s); Exudyn %.1f s; Exudyn / flexrod = %.1f"
              % (case, best, rounds, ", ".join("%.3f" % c for c in cpus), EXUDYN_CPU[case],
                 EXUDYN_CPU[case] / best))
        print("    of which process start-up %.0f %%" % (100.0 * startup / best))
        describe("run", summary)
        describe_shares(run_once(binary, toml, args + extra + ["--profile"])[1])
        if "ideal" in summary and "integrator" in summary["ideal"]:
            describe("twin", summary["ideal"])
        a = summary.get("slider_acceleration", {})
        if a:
            print("    slider acceleration: peak +%.4g / -%.4g m/s^2, p95 of per-revolution |peak| %.4g m/s^2"
                  % (a["peak_positive"], a["peak_negative"], a["per_revolution_abs"]["p95"]))
        amp = summary.get("load_amplification")
        if amp:
            print("    load amplification: slider acceleration +%.4g (p95 %.4g), bearing force %.4g (p95 %.4g)"
                  % (amp["slider_acceleration_positive"], amp["slider_acceleration_positive_p95"],
                     amp["bearing_force"], amp["bearing_force_p95"]))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
