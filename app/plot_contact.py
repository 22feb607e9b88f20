#!/usr/bin/python3
# app/plot_contact.py — plots the force–penetration loop of `flexrod contact --plot`.
# Usage: plot_contact.py LOOP.csv OUT.png TITLE
# LOOP.csv has the header "time [s],penetration [m],rate [m/s],force [N]". The PNG is written to
# a temporary name beside OUT.png and renamed over it, so a failure never leaves a partial file.
# SPDX-License-Identifier: GPL-3.0-or-later
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(argv):
    if len(argv) != 4:
        sys.stderr.write("usage: plot_contact.py LOOP.csv OUT.png TITLE\n")
        return 2
    csv_path, out_path, title = argv[1], argv[2], argv[3]
    penetration_um, force_n, rate = [], [], []
    with open(csv_path, newline="") as f:
        reader = csv.reader(f)
        next(reader)  # header
        for row in reader:
            penetration_um.append(float(row[1]) * 1e6)
            rate.append(float(row[2]))
            force_n.append(float(row[3]))
    if not force_n:
        sys.stderr.write("plot_contact.py: empty loop\n")
        return 1

    fig, ax = plt.subplots(figsize=(6.4, 4.8), dpi=120)
    loading = [(d, f) for d, f, r in zip(penetration_um, force_n, rate) if r >= 0.0]
    unloading = [(d, f) for d, f, r in zip(penetration_um, force_n, rate) if r < 0.0]
    if loading:
        ax.plot(*zip(*loading), color="tab:red", label="approach (rate >= 0)")
    if unloading:
        ax.plot(*zip(*unloading), color="tab:blue", label="restitution (rate < 0)")
    ax.set_xlabel("penetration [um]")
    ax.set_ylabel("normal force [N]")
    ax.set_title(title, fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best")
    fig.tight_layout()

    directory = os.path.dirname(os.path.abspath(out_path))
    tmp_path = os.path.join(directory, ".%s.tmp-%d.png" % (os.path.basename(out_path), os.getpid()))
    try:
        fig.savefig(tmp_path, format="png")
        os.replace(tmp_path, out_path)
    except BaseException:
        if os.path.exists(tmp_path):
            os.remove(tmp_path)
        raise
    finally:
        plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
