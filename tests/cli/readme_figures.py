#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""README figures that cannot go stale.

- The main job (`flexrod run`, the README's first command's job): its report against the block
  the README prints, line by line, every number to the printed digits; wall times are the only
  numbers left out (they vary with the machine), and the output size is checked within 5 %.
- The output sizes the README quotes ("About N MB for the main job", "about N MB" with every
  channel), within 5 %.
- The buckling load: pi^2 E I / L^2 of the main job's rod (weak axis, pinned), from its
  resolved input, to the digits printed.
- The main job's reduced rod against the exact rod with Rayleigh damping (p95 of the
  per-revolution peak slider acceleration, bearing-force amplification, peak gauge stress).
- The modal reduction study with Rayleigh damping (`flexrod study reduction`): the smallest
  Craig–Bampton k within 2 % of the exact rod, and the largest difference of k = 8 and of the
  full FE rod, to the printed digits.
- The damping study (`flexrod study damping`): the main job's positive amplification p95 under
  the band, the ratios 1–5 %, Rayleigh and the material's damping, to the printed digits.
- The rigid rig's guide calibration: the median per-revolution peak |a| at 101 rpm over the
  ideal joint's, at the preset's guide damping and 2 % below and above it, to the printed digits.

  readme_figures.py FLEXROD_BINARY README.md        exit 0 if the README matches
"""
import json
import math
import os
import re
import subprocess
import sys
import tempfile
import tomllib

NUMBER = re.compile(r"[-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?")


def readme_block(readme):
    """The lines of the code block that follows "It prints:" in the README."""
    text = open(readme, encoding="utf-8").read()
    start = text.index("```", text.index("It prints:")) + 3
    end = text.index("```", start)
    return [line for line in text[start:end].splitlines() if line.strip()]


def run(binary, out, *sets):
    """`flexrod run` with --set assignments; returns its stdout (raises on failure)."""
    argv = [binary, "run"]
    preset = [a for a in sets if not "=" in a]
    argv += preset + [x for a in sets if "=" in a for x in ("--set", a)]
    proc = subprocess.run(argv + ["--no-plot", "--out", out], capture_output=True, text=True,
                          timeout=600)
    if proc.returncode != 0:
        raise RuntimeError("flexrod %s failed:\n%s" % (" ".join(argv), proc.stderr))
    return proc.stdout


def files_mb(report):
    """The output size [MB] of a run's report line "files: N MB in T s"."""
    line = next(l for l in report.splitlines() if l.strip().startswith("files:"))
    return float(NUMBER.findall(line)[0])


def readme_text(readme):
    return " ".join(open(readme, encoding="utf-8").read().split())


def check_main_job(binary, readme, tmp, errors):
    expected = readme_block(readme)
    report = run(binary, os.path.join(tmp, "run"))
    actual = [line for line in report.splitlines() if line.strip()]
    actual[0] = actual[0].replace(os.path.join(tmp, "run"), "out/run")
    if len(actual) != len(expected):
        errors.append("%d lines printed, the README has %d" % (len(actual), len(expected)))
    for e, a in zip(expected, actual):
        if "wall" in e:  # the integrator line: its counts must match, its wall time not
            e, a = e.split("wall")[0], a.split("wall")[0]
        if e.strip().startswith("files:"):
            size_e, size_a = float(NUMBER.findall(e)[0]), float(NUMBER.findall(a)[0])
            if abs(size_a - size_e) > 0.05 * size_e:
                errors.append("output size %s MB, the README says %s MB" % (size_a, size_e))
            continue
        if e != a:
            errors.append("README: %s\n  run:    %s" % (e, a))
    return report


def check_sizes(binary, readme, tmp, main_report, errors):
    text = readme_text(readme)
    quoted = float(re.search(r"About (\d+) MB for the main job", text).group(1))
    if abs(files_mb(main_report) - quoted) > 0.05 * quoted:
        errors.append("main job writes %s MB, the README says about %s MB"
                      % (files_mb(main_report), quoted))
    quoted_all = float(re.search(r"energies: about (\d+) MB for the main job", text).group(1))
    written = files_mb(run(binary, os.path.join(tmp, "all"), "output.channels=all"))
    if abs(written - quoted_all) > 0.05 * quoted_all:
        errors.append("output.channels=all writes %s MB, the README says about %s MB"
                      % (written, quoted_all))


def check_buckling(readme, tmp, errors):
    with open(os.path.join(tmp, "run", "resolved.toml"), "rb") as f:
        rod = tomllib.load(f)["rod"]
    assert rod["material"] == "steel" and rod["bending"] == "weak" and rod["E"] == 0
    E = 200e9  # steel's E when rod.E = 0 (fem/material.cc: AISI 1045, MatWeb, 200 GPa)
    inertia = rod["height"] * rod["thickness"] ** 3 / 12.0  # weak axis [m^4]
    p_cr = math.pi ** 2 * E * inertia / rod["length"] ** 2
    quoted = re.search(r"buckle at π²EI/L² ≈ ([\d.]+) kN", readme_text(readme)).group(1)
    if "%.1f" % (p_cr / 1e3) != quoted:
        errors.append("pi^2 EI/L^2 = %.4g N, the README says %s kN" % (p_cr, quoted))


def check_rigid_rig_calibration(binary, readme, tmp, errors):
    text = readme_text(readme)
    m = re.search(r"guide \(1 N Coulomb, ([\d.]+) N s/m\)", text)
    damping = float(m.group(1))
    central = re.search(r"median per-revolution peak \|a\| ([\d.]+) times the ideal", text)
    band = re.search(r"2 % less or more guide damping \(([\d.]+) / ([\d.]+) N s/m\) gives "
                     r"([\d.]+) / ([\d.]+) times", text)
    cases = [(damping, central.group(1)), (float(band.group(1)), band.group(3)),
             (float(band.group(2)), band.group(4))]
    if "%.2f" % (0.98 * damping) != band.group(1) or "%.2f" % (1.02 * damping) != band.group(2):
        errors.append("the README's band is not 2 %% of %s N s/m" % damping)
    for d, quoted in cases:
        out = os.path.join(tmp, "rigid-%s" % d)
        # 20 revolutions at 101 rpm
        run(binary, out, "rigid-rig", "drive.speed=101 rpm", "sim.capture=11.88 s",
            "slider.damping=%r N s/m" % d, "output.channels=crank_angle")
        with open(os.path.join(out, "summary.json")) as f:
            s = json.load(f)
        ratio = (s["slider_acceleration"]["per_revolution_abs"]["median"]
                 / s["ideal"]["slider_acceleration"]["per_revolution_abs"]["median"])
        if "%.1f" % ratio != quoted:
            errors.append("rigid rig, 101 rpm, guide %s N s/m: median per-revolution peak "
                          "ratio %.3f, the README says %s" % (d, ratio, quoted))


def check_exact_rod_comparison(binary, readme, tmp, errors):
    """The main job's reduced rod against the exact rod, both with Rayleigh damping."""
    text = readme_text(readme)
    m = re.search(r"the p95 of the per-revolution peak slider acceleration ([\d.]+) against "
                  r"([\d.]+) m/s², the bearing-force amplification ([\d.]+) against ([\d.]+), "
                  r"the peak gauge stress ([\d.]+) against ([\d.]+) MPa", text)
    for k, rod in enumerate(("flexible", "exact")):
        out = os.path.join(tmp, "rayleigh-%s" % rod)
        run(binary, out, "rod.type=" + rod, "damping.type=rayleigh", "damping.beta=2e-5",
            "output.channels=crank_angle")
        with open(os.path.join(out, "summary.json")) as f:
            s = json.load(f)
        figures = ["%.1f" % s["slider_acceleration"]["per_revolution_abs"]["p95"],
                   "%.2f" % s["load_amplification"]["bearing_force"],
                   "%.2f" % (s["rod"]["peak_gauge_stress [Pa]"] / 1e6)]
        quoted = [m.group(1 + k), m.group(3 + k), m.group(5 + k)]
        if figures != quoted:
            errors.append("rod.type = %s with Rayleigh damping: %s, the README says %s"
                          % (rod, figures, quoted))


def check_reduction_study(binary, readme, tmp, errors):
    """The reduction study's verdict and its k = 8 and full-FE differences to the exact rod."""
    text = readme_text(readme)
    m = re.search(r"Craig–Bampton is within 2 % on every figure from k = (\d+) modes \(k = 8: "
                  r"([\d.]+) %; full FE, [^:]*: ([\d.]+) %\)", text)
    out = os.path.join(tmp, "study")
    argv = [binary, "study", "reduction", "--no-plot", "--out", out, "--set",
            "damping.type=rayleigh", "--set", "damping.beta=2e-5"]
    proc = subprocess.run(argv, capture_output=True, text=True, timeout=900)
    if proc.returncode != 0:
        errors.append("flexrod %s failed:\n%s" % (" ".join(argv[1:]), proc.stderr))
        return
    verdict = open(os.path.join(out, "verdict.txt"), encoding="utf-8").read()
    k = re.search(r"within 2 % of the exact rod on every figure: (\d+)", verdict)
    if k is None or k.group(1) != m.group(1):
        errors.append("reduction study: %s, the README says from k = %s"
                      % (verdict.strip(), m.group(1)))
    with open(os.path.join(out, "table.csv"), encoding="utf-8") as f:
        rows = {r[0]: r for r in (line.rstrip("\n").split(",") for line in f)}
    column = rows["variant"].index("max |diff.| [%]")
    for variant, quoted in (("cb-8", m.group(2)), ("full", m.group(3))):
        value = "%.2f" % float(rows[variant][column])
        if value != quoted:
            errors.append("reduction study: %s within %s %% of the exact rod, the README says %s %%"
                          % (variant, value, quoted))


def check_damping_study(binary, readme, tmp, errors):
    """The damping study's positive amplification p95 per damping model, to the printed digits."""
    text = readme_text(readme)
    m = re.search(r"the positive amplification p95 is ([\d.]+) with the band, ([\d.]+)–([\d.]+) "
                  r"with 1–5 % on every mode, ([\d.]+) with Rayleigh β = 2e-5 s and ([\d.]+) with "
                  r"the metal's own damping", text)
    if m is None:
        errors.append("README: the damping study's sentence is missing")
        return
    out = os.path.join(tmp, "damping")
    argv = [binary, "study", "damping", "--no-plot", "--out", out]
    proc = subprocess.run(argv, capture_output=True, text=True, timeout=900)
    if proc.returncode != 0:
        errors.append("flexrod %s failed:\n%s" % (" ".join(argv[1:]), proc.stderr))
        return
    with open(os.path.join(out, "table.csv"), encoding="utf-8") as f:
        rows = {r[0]: r for r in (line.rstrip("\n").split(",") for line in f)}
    column = rows["damping"].index("amplification + (p95)")
    ratios = sorted((rows[v][column] for v in ("ratio-1%", "ratio-2%", "ratio-5%")), key=float)
    for name, value, quoted in (("band", rows["band"][column], m.group(1)),
                                ("ratio, lowest", ratios[0], m.group(2)),
                                ("ratio, highest", ratios[-1], m.group(3)),
                                ("rayleigh", rows["rayleigh-2e-5"][column], m.group(4)),
                                ("material", rows["material"][column], m.group(5))):
        if value != quoted:  # the table's own 4 significant digits
            errors.append("damping study: %s %s, the README says %s" % (name, value, quoted))


def main(argv):
    binary, readme = argv[1], argv[2]
    errors = []
    with tempfile.TemporaryDirectory() as tmp:
        report = check_main_job(binary, readme, tmp, errors)
        check_sizes(binary, readme, tmp, report, errors)
        check_buckling(readme, tmp, errors)
        check_rigid_rig_calibration(binary, readme, tmp, errors)
        check_exact_rod_comparison(binary, readme, tmp, errors)
        check_reduction_study(binary, readme, tmp, errors)
        check_damping_study(binary, readme, tmp, errors)
    for err in errors:
        print(err)
    print("%d README figures differ" % len(errors))
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
