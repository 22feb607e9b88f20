#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The seven rods of RIG.md Table 1 with the 0.5 mm clearance joint: load amplification
(p95 of the per-revolution peak |slider acceleration|, real / ideal joint) against crank speed,
one line per rod, and the table at 200 rpm.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/rods_amplification.py [--quick]
        [--out DIR]

Writes DIR/rods_amplification.png and DIR/rods_amplification.csv (default out/python).
--quick (or FLEXROD_EXAMPLE_QUICK=1): two speeds and a short capture, for the test suite.
The full version runs 7 rods x 16 speeds (100-250 rpm) with the preset's capture: about an
hour on one core.
"""

import argparse
import csv
import os
import sys
import tomllib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import flexrod  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def seven_rods():
    """(material, height) of the seven rods: the zipped axis of the Table 2 matrix."""
    with open(os.path.join(HERE, "..", "sweep-table2.toml"), "rb") as f:
        matrix = tomllib.load(f)
    return [tuple(r) for r in matrix["axes"]["rod.material,rod.height"]]


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true",
                   default=os.environ.get("FLEXROD_EXAMPLE_QUICK") == "1")
    p.add_argument("--out", default="out/python")
    args = p.parse_args(argv)

    if args.quick:
        speeds = [150, 200]  # rpm; two revolutions at 150 rpm, for the per-revolution p95
        base = {"sim.settle": "0.1 s", "sim.capture": "0.8 s", "sim.sample_rate": "10 kHz"}
    else:
        speeds = list(range(100, 251, 10))
        base = {}
    base = {**base, "joint.type": "clearance", "joint.clearance": "0.5 mm"}

    rows = []  # (rod, speed [rpm], amplification + (p95), amplification - (p95), bearing [1])
    for material, height in seven_rods():
        for rpm in speeds:
            r = flexrod.run("flexible-rig", set={**base, "rod.material": material,
                                                  "rod.height": height,
                                                  "drive.speed": f"{rpm} rpm"})
            a = r.summary["load_amplification"]
            nan = float("nan")  # a ratio is null where undefined (e.g. no complete revolution)
            rows.append((f"{material} {height}", rpm,
                         a["slider_acceleration_positive_p95"] or nan,
                         a["slider_acceleration_negative_p95"] or nan,
                         a["bearing_force"] or nan))
            print(f"{material:9s} {height:8s} {rpm:4d} rpm: amplification +{rows[-1][2]:.3g} "
                  f"/ -{rows[-1][3]:.3g}, bearing force {rows[-1][4]:.3g}", flush=True)

    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "rods_amplification.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["rod", "speed [rpm]", "amplification + (p95) [1]",
                    "amplification - (p95) [1]", "bearing force amplification [1]"])
        w.writerows(rows)

    print("\nat 200 rpm, 0.5 mm clearance (p95 of per-revolution peaks, real / ideal):")
    for rod, rpm, pos, neg, bearing in rows:
        if rpm == 200:
            print(f"  {rod:20s} +{pos:6.3g} / -{neg:6.3g}   bearing force {bearing:6.3g}")

    fig, ax = plt.subplots(figsize=(7, 4.5))
    for i, rod in enumerate(dict.fromkeys(r[0] for r in rows)):
        mine = [r for r in rows if r[0] == rod]
        ax.plot([r[1] for r in mine], [max(r[2], r[3]) for r in mine], "o-", color=f"C{i}",
                label=rod)
    ax.axvline(200, color="k", lw=0.6, ls=":")
    ax.set_xlabel("crank speed [rpm]")
    ax.set_ylabel("load amplification, p95 of per-rev. peak |slider acc.| [1]")
    ax.set_title("seven rods, 0.5 mm clearance")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    png = os.path.join(args.out, "rods_amplification.png")
    fig.savefig(png, dpi=120)
    print(f"plot: {png}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
