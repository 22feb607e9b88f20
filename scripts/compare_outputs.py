#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Compares two output trees of scripts/produce_outputs.sh: every HDF5 dataset and attribute
(values, exactly), every summary.json value but wall and CPU times, every other file byte by
byte except the printed wall times. Prints each difference; exit 1 if any.
Usage: compare_outputs.py DIR_A DIR_B      (Debian's /usr/bin/python3 with h5py, numpy)"""
import json
import pathlib
import re
import sys

import h5py
import numpy as np

TIMES = re.compile(r"(wall|cpu|seconds|elapsed|output_time)", re.I)
PRINTED_TIME = re.compile(rb"[0-9.]+ ?(ms|s|MB)\b")


def h5_items(path):
    out = {}
    with h5py.File(path, "r") as f:
        def visit(name, obj):
            for k, v in obj.attrs.items():
                out["%s@%s" % (name, k)] = v
            if isinstance(obj, h5py.Dataset):
                out[name] = obj[()]
        f.visititems(visit)
        for k, v in f.attrs.items():
            out["/@" + k] = v
    return out


def same(a, b):
    a, b = np.asarray(a), np.asarray(b)
    if a.shape != b.shape or a.dtype != b.dtype:
        return False
    if a.dtype.kind == "f":
        return np.array_equal(a, b, equal_nan=True)
    return np.array_equal(a, b)


def json_diff(a, b, where, out):
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if TIMES.search(k):
                continue
            if k not in a or k not in b:
                out.append("%s/%s: only in one" % (where, k))
            else:
                json_diff(a[k], b[k], where + "/" + k, out)
    elif isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        for i, (x, y) in enumerate(zip(a, b)):
            json_diff(x, y, "%s[%d]" % (where, i), out)
    elif a != b and not (a != a and b != b):
        out.append("%s: %r != %r" % (where, a, b))


def main():
    a, b = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
    files = sorted({p.relative_to(a) for p in a.rglob("*") if p.is_file()} |
                   {p.relative_to(b) for p in b.rglob("*") if p.is_file()})
    diffs = []
    for rel in files:
        pa, pb = a / rel, b / rel
        if not pa.exists() or not pb.exists():
            diffs.append("%s: only in one tree" % rel)
            continue
        if rel.suffix == ".h5":
            ia, ib = h5_items(pa), h5_items(pb)
            for k in sorted(set(ia) | set(ib)):
                if TIMES.search(k.split("/")[-1]):
                    continue
                if k not in ia or k not in ib:
                    diffs.append("%s:%s only in one" % (rel, k))
                elif k.endswith("summary_json"):
                    json_diff(json.loads(ia[k]), json.loads(ib[k]), "%s:%s" % (rel, k), diffs)
                elif not same(ia[k], ib[k]):
                    diffs.append("%s:%s differs" % (rel, k))
        elif rel.suffix == ".json":
            out = []
            json_diff(json.loads(pa.read_text()), json.loads(pb.read_text()), str(rel), out)
            diffs += out
        else:
            ta, tb = pa.read_bytes(), pb.read_bytes()
            if rel.suffix == ".stdout":
                ta = PRINTED_TIME.sub(b"T", ta.replace(str(a).encode(), b"DIR"))
                tb = PRINTED_TIME.sub(b"T", tb.replace(str(b).encode(), b"DIR"))
            if ta != tb:
                diffs.append("%s: bytes differ" % rel)
    for d in diffs:
        print(d)
    print("%d files, %d differences" % (len(files), len(diffs)))
    return 1 if diffs else 0


if __name__ == "__main__":
    sys.exit(main())
