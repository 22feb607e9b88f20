#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""flexrod plots (matplotlib, Agg backend). Run with Debian's /usr/bin/python3.

  flexrod_plots.py run DIR      DIR/channels.csv (+ DIR/ideal/channels.csv) -> DIR/*.png
Every PNG is written to a temporary name and renamed, so no half-written plot is left.
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header = rows[0]
    cols = {h: [] for h in header}
    for r in rows[1:]:
        if not r:
            continue
        for h, v in zip(header, r):
            cols[h].append(float(v))
    return cols


def save(fig, path):
    tmp = path + ".tmp.png"
    fig.savefig(tmp, dpi=120)
    plt.close(fig)
    os.replace(tmp, path)


def plot_run(directory):
    cols = read_csv(os.path.join(directory, "channels.csv"))
    ideal_path = os.path.join(directory, "ideal", "channels.csv")
    ideal = read_csv(ideal_path) if os.path.exists(ideal_path) else None
    if "crank_angle [rad]" in cols:
        fig, ax = plt.subplots(figsize=(9, 4.5))
        ang = [math.degrees(a % (2 * math.pi)) for a in cols["crank_angle [rad]"]]
        ax.plot(ang, cols["slider_acceleration [m/s^2]"], ",", color="C0", label="model")
        if ideal:
            ang_i = [math.degrees(a % (2 * math.pi)) for a in ideal["crank_angle [rad]"]]
            ax.plot(ang_i, ideal["slider_acceleration [m/s^2]"], ",", color="C3", label="ideal joint")
            ax.legend(markerscale=20)
        ax.set_xlabel("crank angle [deg]")
        ax.set_ylabel("slider acceleration [m/s^2]")
        ax.set_xlim(0, 360)
        ax.grid(True, alpha=0.3)
        save(fig, os.path.join(directory, "slider_acceleration.png"))
    strains = [h for h in cols if h.startswith("strain_")]
    if strains:
        fig, ax = plt.subplots(figsize=(9, 4.5))
        for h in strains:
            ax.plot(cols["time [s]"], [1e6 * v for v in cols[h]], lw=0.6, label=h.split(" ")[0])
        ax.set_xlabel("time [s]")
        ax.set_ylabel("surface strain [µm/m]")
        ax.legend()
        ax.grid(True, alpha=0.3)
        save(fig, os.path.join(directory, "rod_strain.png"))


def main(argv):
    if len(argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    if argv[1] == "run":
        plot_run(argv[2])
        return 0
    print("unknown plot kind: " + argv[1], file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
