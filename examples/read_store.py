#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Read a flexrod sweep store (the HDF5 file `flexrod sweep` writes), or the run.h5 of one run
(`flexrod run`), with h5py.

  read_store.py STORE.h5                one line per run: id, status, matrix values, peaks,
                                        load amplification
  read_store.py STORE.h5 --run ID       one run: its summary, its datasets with shape and unit,
                                        the turning points of the slider acceleration
  read_store.py STORE.h5 --input ID     the run's complete input as TOML; `flexrod run FILE`
                                        reruns exactly that run
  read_store.py STORE.h5 --check-units  exit status 1 if any dataset lacks its "unit" attribute
  read_store.py DIR/run.h5              one run (as --run), with its ideal twin's channels
  read_store.py DIR/run.h5 --input      its complete input as TOML
  read_store.py DIR/run.h5 --check-units

Layout (docs/sweeps.md): /runs/run_NNNNN with the resolved inputs as attributes (key = SI
value, "<key>.unit"), groups summary, inflection_points/{positive,negative},
poincare, spectrum and channels; every dataset carries an attribute "unit". A run.h5 has the
layout of one run at its root, plus ideal/channels (the ideal-joint twin) and impacts/<column>
(the impact log); channels/<name> holds output.channels at output.rate (attributes sample_rate,
start_time: sample i is at start_time + i / sample_rate).
"""
import math
import sys

import h5py
import numpy as np


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def long_text(attrs, name):
    """A text attribute; texts over 60000 bytes continue in "<name>.1", "<name>.2", ..."""
    out, k = text(attrs[name]), 1
    while "%s.%d" % (name, k) in attrs:
        out += text(attrs["%s.%d" % (name, k)])
        k += 1
    return out


def datasets(group, prefix=""):
    """(path, dataset) for every dataset below group."""
    out = []
    for name, item in group.items():
        if isinstance(item, h5py.Dataset):
            out.append((prefix + name, item))
        else:
            out.extend(datasets(item, prefix + name + "/"))
    return out


def list_runs(f):
    print("%s: %d runs, %d failed (matrix keys: %s)" % (text(f.attrs["name"]), int(f.attrs["num_runs"]),
                                                       int(f.attrs["num_failed"]), long_text(f.attrs, "axes")))
    for name in sorted(f["runs"]):
        run = f["runs"][name]
        s = run["summary"].attrs
        amp = [s.get("amplification_positive", math.nan), s.get("amplification_negative", math.nan)]
        peaks = [s.get("peak_positive", math.nan), s.get("peak_negative", math.nan)]
        print("%5d %-18s %-60s peak +%.4g/-%.4g m/s^2  amplification +%.3g/-%.3g" % (
            int(run.attrs["run_id"]), text(run.attrs["status"]), long_text(run.attrs, "label"), peaks[0], peaks[1],
            amp[0], amp[1]))


def show_run(run, title):
    print("%s: %s  %s" % (title, text(run.attrs["status"]), long_text(run.attrs, "label")))
    if long_text(run.attrs, "message"):
        print("  message:", long_text(run.attrs, "message"))
    for key in ("rod.material", "rod.height", "joint.type", "joint.clearance", "drive.speed"):
        if key in run.attrs:
            unit = text(run.attrs[key + ".unit"]) if key + ".unit" in run.attrs else ""
            print("  %-18s %s %s" % (key, text(run.attrs[key]), unit))
    s = run["summary"].attrs
    for name in text(s["names"]).split(","):
        print("  summary %-28s %.6g %s" % (name, s[name], text(s[name + ".unit"])))
    for path, d in datasets(run):
        print("  dataset %-42s shape %-10s unit %s" % (path, d.shape, text(d.attrs.get("unit", "MISSING"))))
    neg = run["inflection_points/negative/value"][()]
    if neg.size:
        print("  negative turning points: %d, median |a| = %.4g m/s^2" % (neg.size, np.median(np.abs(neg))))


def check_units(groups):
    """Exit status 1 if a dataset below any of `groups` (name -> group) lacks its unit."""
    missing = [name + "/" + path for name in groups for path, d in datasets(groups[name])
               if "unit" not in d.attrs]
    count = sum(len(datasets(groups[name])) for name in groups)
    print("%d datasets, %d without a unit" % (count, len(missing)))
    for m in missing[:20]:
        print("  no unit:", m)
    return 1 if missing else 0


def main(argv):
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    with h5py.File(argv[1], "r") as f:
        if text(f.attrs.get("format", "")).startswith("flexrod-run"):  # one run's run.h5
            if len(argv) == 2:
                show_run(f, argv[1])
            elif argv[2] == "--input":
                sys.stdout.write(long_text(f.attrs, "input_toml"))
            elif argv[2] == "--check-units":
                return check_units({argv[1]: f})
            else:
                print(__doc__, file=sys.stderr)
                return 2
            return 0
        if len(argv) == 2:
            list_runs(f)
        elif argv[2] == "--run":
            show_run(f["runs"]["run_%05d" % int(argv[3])], "run " + argv[3])
        elif argv[2] == "--input":
            sys.stdout.write(long_text(f["runs"]["run_%05d" % int(argv[3])].attrs, "input_toml"))
        elif argv[2] == "--check-units":
            return check_units(f["runs"])
        else:
            print(__doc__, file=sys.stderr)
            return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
