# SPDX-License-Identifier: GPL-3.0-or-later
"""Shared helpers of the flexrod Python tests: the CLI next to the module, and readers of its
output files. Run by ctest (python.pytest) with PYTHONPATH=build/python."""

import csv
import json
import os
import subprocess

import h5py
import numpy as np
import pytest

BINARY = os.environ.get("FLEXROD_BINARY", "")
SOURCE_DIR = os.environ.get(
    "FLEXROD_SOURCE_DIR", os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..")))
PYTHON = "/usr/bin/python3"

# Cheap settings for runs compared with the CLI: the flexible rig's clearance joint, 0.05 s of
# settling and 0.15 s captured at 20 kHz (the twin too).
SHORT = {"sim.settle": "0.05 s", "sim.capture": "0.15 s", "sim.sample_rate": "20 kHz"}

# Summary entries that are wall-clock times, not results.
TIMING_KEYS = {"wall_time [s]", "output_time [s]"}


def cli(*args, check=True):
    """Runs the flexrod executable; returns the CompletedProcess (text output)."""
    if not BINARY:
        pytest.skip("FLEXROD_BINARY is not set (ctest sets it)")
    proc = subprocess.run([BINARY, *args], capture_output=True, text=True)
    if check and proc.returncode != 0:
        raise AssertionError(f"flexrod {' '.join(args)} exited {proc.returncode}:\n{proc.stderr}")
    return proc


def set_args(sets):
    out = []
    for k, v in sets.items():
        out += ["--set", f"{k}={v}"]
    return out


def without_timing(obj):
    """The summary without its wall-clock entries (recursively)."""
    if isinstance(obj, dict):
        return {k: without_timing(v) for k, v in obj.items() if k not in TIMING_KEYS}
    if isinstance(obj, list):
        return [without_timing(v) for v in obj]
    return obj


def read_summary(directory):
    with open(os.path.join(directory, "summary.json")) as f:
        return json.load(f)


def read_cli_channels(directory, group="channels"):
    """The channels `flexrod run --out DIR` wrote into DIR/run.h5 (`group`: "channels", or
    "ideal/channels" for the twin), {name: float64 array} with "time" first (start_time +
    i / sample_rate, as the module computes it) and {name: unit}, in the file's order."""
    with h5py.File(os.path.join(directory, "run.h5"), "r") as f:
        g = f[group]
        names = g.attrs["names"].decode().split(",")
        n = len(g[names[0]])
        channels = {"time": g.attrs["start_time"] + np.arange(n) / g.attrs["sample_rate"]}
        units = {"time": "s"}
        for name in names:
            channels[name] = g[name][:]
            units[name] = g[name].attrs["unit"].decode()
        return channels, units


def read_cli_impacts(directory):
    """The impact log of DIR/run.h5: {column: float64 array}, {column: unit}, in order."""
    with h5py.File(os.path.join(directory, "run.h5"), "r") as f:
        g = f["impacts"]
        names = g.attrs["names"].decode().split(",")
        return ({name: g[name][:] for name in names},
                {name: g[name].attrs["unit"].decode() for name in names})


def read_csv_columns(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    names, units = [], {}
    for h in header:
        name, unit = h.rsplit(" [", 1)
        names.append(name)
        units[name] = unit.rstrip("]")
    data = np.array([[float(x) for x in r] for r in body], dtype=np.float64).reshape(
        len(body), len(names))
    return {n: data[:, i].copy() for i, n in enumerate(names)}, units


def h5_items(path):
    """Every dataset (values) and attribute of an HDF5 file, by path; a run's summary JSON
    (attribute summary_json, continued in summary_json.1, ...) parsed, without its wall-clock
    entries; the attribute wall_time left out."""
    items, summaries = {}, {}

    def visit(name, obj):
        for k, v in obj.attrs.items():
            if k == "wall_time":
                continue
            if k.startswith("summary_json"):
                summaries.setdefault(name, {})[k] = v
                continue
            items[f"{name}@{k}"] = v
        if isinstance(obj, h5py.Dataset):
            items[name] = obj[()]

    with h5py.File(path, "r") as f:
        visit("/", f)
        f.visititems(visit)
    for name, parts in summaries.items():
        order = sorted(parts, key=lambda k: int(k.rsplit(".", 1)[1]) if "." in k else 0)
        text = "".join(p.decode() if isinstance(p, bytes) else str(p) for p in
                       (parts[k] for k in order))
        items[f"{name}@summary_json"] = json.dumps(without_timing(json.loads(text)),
                                                   sort_keys=True)
    return items


def same_h5(a, b):
    """True if two HDF5 files hold the same datasets and attributes (NaN equal to NaN),
    wall-clock entries aside; raises AssertionError naming the first difference."""
    x, y = h5_items(a), h5_items(b)
    assert sorted(x) == sorted(y)
    for k in x:
        u, v = np.asarray(x[k]), np.asarray(y[k])
        assert np.array_equal(u, v, equal_nan=u.dtype.kind in "fc"), k
    return True


@pytest.fixture(scope="session")
def source_dir():
    return SOURCE_DIR
