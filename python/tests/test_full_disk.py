# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes on a real full disk (issue 60, item 1): a 300 kB tmpfs fills while a run or a sweep
writes its HDF5 files. The CLI exits 3 naming the file and the system's reason, with no crash at
exit (HDF5 used to segfault in its clean-up on the file that failed to close) and no half-written
file; a sweep keeps its finished runs; Python raises flexrod.IoError (an OSError) and the
interpreter exits normally. Skipped where mounting a tmpfs is not permitted (not root)."""

import os
import subprocess
import sys

import pytest

from conftest import cli, PYTHON

FILL = ["--no-plot", "--set", "sim.settle=0", "--set", "sim.capture=0.5 s", "--set",
        "ensemble.members=1"]


@pytest.fixture
def full_disk(tmp_path):
    mount = tmp_path / "small"
    mount.mkdir()
    try:
        subprocess.run(["mount", "-t", "tmpfs", "-o", "size=300k", "tmpfs", str(mount)],
                       check=True, capture_output=True, text=True)
    except (OSError, subprocess.CalledProcessError) as e:
        pytest.skip(f"mounting a tmpfs is not permitted here: {getattr(e, 'stderr', e)}")
    yield mount
    subprocess.run(["umount", str(mount)], check=False)


def test_run_on_a_full_disk_exits_3_with_the_reason(full_disk):
    out = full_disk / "r"
    proc = cli("run", *FILL, "--out", str(out), check=False)
    assert proc.returncode == 3, proc.stderr
    assert "No space left on device" in proc.stderr
    assert str(out / "run.h5") in proc.stderr
    assert len(proc.stderr.strip().splitlines()) <= 3, proc.stderr  # no HDF5 error stack
    assert not (out / "run.h5").exists() and not (out / "run.h5.tmp").exists()


def test_sweep_on_a_full_disk_exits_3_and_keeps_its_finished_runs(full_disk):
    store = full_disk / "s.h5"
    args = ["sweep", "sweep-small", "--jobs", "1", "--no-plot", "--set", "sim.settle=0", "--set",
            "sim.capture=1 s", "--out", str(store)]
    first = cli(*args, check=False)
    assert first.returncode == 3, first.stderr
    assert "No space left on device" in first.stderr
    assert "Traceback" not in first.stderr and "HDF5-DIAG" not in first.stderr
    again = cli(*args, check=False)
    assert again.returncode == 3, again.stderr
    assert "1 already finished" in again.stdout + again.stderr


def test_python_raises_ioerror_and_exits_normally(full_disk):
    script = (
        "import flexrod, sys\n"
        "try:\n"
        f"    flexrod.run(set={{'sim.settle': 0, 'sim.capture': '0.5 s', 'ensemble.members': 1}},"
        f" out={str(full_disk / 'p')!r})\n"
        "except flexrod.IoError as e:\n"
        "    assert isinstance(e, OSError)\n"
        "    print('IoError:', e)\n"
        "    sys.exit(0)\n"
        "sys.exit(5)\n")
    proc = subprocess.run([PYTHON, "-c", script], capture_output=True, text=True,
                          env=dict(os.environ))
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "No space left on device" in proc.stdout
