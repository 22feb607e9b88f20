# SPDX-License-Identifier: GPL-3.0-or-later
"""examples/python/*.py run on a short horizon (--quick), with /usr/bin/python3."""

import csv
import os
import subprocess

import pytest

from conftest import PYTHON, SOURCE_DIR


def run_example(name, out, *args):
    env = {**os.environ, "MPLBACKEND": "Agg"}
    proc = subprocess.run([PYTHON, os.path.join(SOURCE_DIR, "examples", "python", name),
                           "--quick", "--out", str(out), *args],
                          capture_output=True, text=True, env=env)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return proc.stdout


def test_rods_amplification_example(tmp_path):
    text = run_example("rods_amplification.py", tmp_path)
    assert (tmp_path / "rods_amplification.png").stat().st_size > 0
    with open(tmp_path / "rods_amplification.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 7 * 2  # seven rods at two speeds
    assert len({r["rod"] for r in rows}) == 7
    assert all(float(r["amplification + (p95) [1]"]) > 0 for r in rows)
    assert "at 200 rpm" in text


def test_reduction_convergence_example(tmp_path):
    run_example("reduction_convergence.py", tmp_path)
    assert (tmp_path / "convergence.png").stat().st_size > 0
    with open(tmp_path / "table.csv", newline="") as f:
        rows = list(csv.reader(f))
    variants = [r[0] for r in rows[1:]]
    assert variants[0] == "exact" and "cb-8" in variants and "free-free-8" in variants
    exact = rows[1]
    assert all(x in ("0", "n/a") for x in exact[3:-2:2])  # the reference differs by 0 from itself
