#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""flexrod plots (matplotlib, Agg backend). Run with Debian's /usr/bin/python3.

  flexrod_plots.py run DIR [--wait]   DIR/run.h5 (or channels.csv + ideal/channels.csv) -> PNGs;
                                      --wait: import now, plot when stdin says "go"
  flexrod_plots.py sweep SUMMARY.csv OUT.png   amplification factor vs speed (flexrod sweep)
  flexrod_plots.py compare DIR  DIR/comparison_NN_points.csv -> 3-D scatter and plan view PNGs
  flexrod_plots.py damping DIR  DIR/table.csv (flexrod study damping) -> DIR/damping.png
Every PNG is written to a temporary name and renamed, so no half-written plot is left.
"""
import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read_csv(path, wanted):
    """Columns of a channels CSV whose header is in `wanted` or starts with one of its entries
    ending in "_" (a prefix), as numpy arrays by header. numpy's C parser reads only those."""
    with open(path, newline="") as f:
        header = next(csv.reader(f))

    def keep(h):
        return any(h == w or (w.endswith("_") and h.startswith(w)) for w in wanted)

    idx = [i for i, h in enumerate(header) if keep(h)]
    if not idx:
        return {}
    data = np.loadtxt(path, delimiter=",", skiprows=1, usecols=idx, ndmin=2)
    return {header[i]: data[:, k] for k, i in enumerate(idx)}


def save(fig, path):
    tmp = path + ".tmp.png"
    fig.savefig(tmp, dpi=120)
    plt.close(fig)
    os.replace(tmp, path)


def read_h5(path, group, wanted):
    """The channels of `group` in a run.h5 whose "name [unit]" is in `wanted` or starts with an
    entry ending in "_", keyed "name [unit]", plus "time [s]" from the group's sample_rate and
    start_time. None if the group is absent."""
    import h5py
    with h5py.File(path, "r") as f:
        if group not in f:
            return None
        g = f[group]
        out = {}
        for name in g:
            unit = g[name].attrs["unit"]
            key = "%s [%s]" % (name, unit.decode() if isinstance(unit, bytes) else unit)
            if any(key == w or (w.endswith("_") and key.startswith(w)) for w in wanted):
                out[key] = g[name][:]
        n = max((len(v) for v in out.values()), default=0)
        out["time [s]"] = g.attrs["start_time"] + np.arange(n) / g.attrs["sample_rate"]
        return out


def stored_spectrum(directory):
    """(frequency [Hz], amplitude, window) of the slider acceleration stored in run.h5, or None."""
    path = os.path.join(directory, "run.h5")
    if not os.path.exists(path):
        return None
    import h5py
    with h5py.File(path, "r") as f:
        if "spectrum/frequency" not in f or len(f["spectrum/frequency"]) < 2:
            return None
        window = f["spectrum"].attrs["window"]
        return (f["spectrum/frequency"][:], f["spectrum/amplitude"][:],
                window.decode() if isinstance(window, bytes) else str(window))


def envelope(ax, x, y, lo, hi, color, label=None, pixels=1100):
    """Per-pixel-column min/max band of y over x in [lo, hi]: what every sample drawn as a dot
    would show, at the cost of 2 x `pixels` points instead of every sample."""
    x = np.asarray(x)
    y = np.asarray(y)
    if len(x) == 0:
        return
    col = np.clip(((x - lo) / (hi - lo) * pixels).astype(np.int64), 0, pixels - 1)
    order = np.argsort(col, kind="stable")
    col, ys = col[order], y[order]
    starts = np.concatenate(([0], np.nonzero(np.diff(col))[0] + 1))
    centres = lo + (col[starts] + 0.5) * (hi - lo) / pixels
    lower = np.minimum.reduceat(ys, starts)
    upper = np.maximum.reduceat(ys, starts)
    ax.fill_between(centres, lower, upper, step="mid", color=color, lw=0.6, edgecolor=color,
                    label=label)


def read_run(directory, wanted, with_ideal=True):
    """(channels, ideal twin's channels or None) of a run directory: run.h5, else the CSVs."""
    h5 = os.path.join(directory, "run.h5")
    if os.path.exists(h5):
        ideal = read_h5(h5, "ideal/channels", wanted) if with_ideal else None
        return read_h5(h5, "channels", wanted), ideal
    cols = read_csv(os.path.join(directory, "channels.csv"), wanted)
    ideal_path = os.path.join(directory, "ideal", "channels.csv")
    if not with_ideal or not os.path.exists(ideal_path):
        return cols, None
    return cols, read_csv(ideal_path, wanted)


def plot_run(directory):
    """The run's PNGs, in two processes (each reads only the channels it draws)."""
    pid = os.fork()
    if pid == 0:  # child: the rod and the joint
        code = 1
        try:
            plot_run_rod_and_joint(directory)
            code = 0
        finally:
            os._exit(code)  # a traceback, if any, is already on stderr
    plot_run_slider(directory)
    _, status = os.waitpid(pid, 0)
    if status != 0:
        raise RuntimeError("plotting the rod and the joint failed")


def regime_title(directory):
    """The run's regime (summary.json: its window's, its ensemble's steady states and interval),
    one line for a plot's title; "" without a summary or a regime."""
    try:
        with open(os.path.join(directory, "summary.json"), encoding="utf-8") as f:
            s = json.load(f)
    except (OSError, ValueError):
        return ""
    parts = []
    if "regime" in s:
        parts.append("window: " + s["regime"]["window"])
    e = s.get("ensemble", {})
    if "regime" in e:
        parts.append("ensemble of %d: %s" % (e["members"], e["regime"]["label"].split(";")[0]))
        f = e.get("figures", {}).get("slider_acceleration_positive_p95")
        if f and "interval" in f:
            parts.append("amplification p95 +%.3g [%.3g, %.3g]" %
                         (f["centre"], f["interval"][0], f["interval"][1]))
    return "; ".join(parts)


def plot_run_slider(directory):
    """Slider acceleration against the ideal twin, its spectrum, the Poincare map."""
    need = ("crank_angle [rad]", "slider_acceleration [m/s^2]")
    cols, ideal = read_run(directory, need + ("time [s]", "journal_eccentricity_x [m]",
                                              "journal_eccentricity_y [m]"))
    # A run's files may hold a selection of channels (output.channels): draw what they have.
    if not all(h in cols for h in need):
        return
    if ideal is not None and not all(h in ideal for h in need):
        ideal = None
    fig, ax = plt.subplots(figsize=(9, 4.5))
    ang = np.degrees(np.mod(cols["crank_angle [rad]"], 2 * math.pi))
    envelope(ax, ang, cols["slider_acceleration [m/s^2]"], 0, 360, "C0", "model")
    if ideal:
        ang_i = np.degrees(np.mod(ideal["crank_angle [rad]"], 2 * math.pi))
        envelope(ax, ang_i, ideal["slider_acceleration [m/s^2]"], 0, 360, "C3", "ideal joint")
        ax.legend()
    ax.set_xlabel("crank angle [deg]")
    ax.set_ylabel("slider acceleration [m/s^2] (range over the revolutions)")
    title = regime_title(directory)
    if title:
        ax.set_title(title, fontsize=9)
    ax.set_xlim(0, 360)
    ax.grid(True, alpha=0.3)
    save(fig, os.path.join(directory, "slider_acceleration.png"))
    plot_spectrum_and_poincare(directory, cols)


def plot_run_rod_and_joint(directory):
    """Gauge strains against time, the journal orbit, the bearing force against crank angle."""
    cols, _ = read_run(directory, ("time [s]", "crank_angle [rad]", "journal_eccentricity_x [m]",
                                   "journal_eccentricity_y [m]", "bearing_force [N]", "strain_"),
                       with_ideal=False)
    strains = [h for h in cols if h.startswith("strain_")]
    if strains:
        fig, ax = plt.subplots(figsize=(9, 4.5))
        t = cols["time [s]"]
        for k, h in enumerate(strains):
            envelope(ax, t, 1e6 * cols[h], t[0], t[-1], "C%d" % k, h.split(" ")[0])
        ax.set_xlim(t[0], t[-1])
        ax.set_xlabel("time [s]")
        ax.set_ylabel("surface strain [µm/m]")
        ax.legend()
        ax.grid(True, alpha=0.3)
        save(fig, os.path.join(directory, "rod_strain.png"))
    plot_orbit_and_bearing_force(directory, cols)


def _float(text):
    try:
        return float(text)
    except ValueError:
        return math.nan


def plot_sweep(summary_csv, out_png):
    """Amplification factor vs speed: one line per rod (every varying value except speed and
    clearance), one panel per clearance (rows) and direction (columns). Without an ideal twin
    (no clearance joint) the peak accelerations are drawn instead."""
    with open(summary_csv, newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["status"] == "completed"]
    amp_cols = ("amplification_positive [1]", "amplification_negative [1]")
    use_amp = any(math.isfinite(_float(r[c])) for r in rows for c in amp_cols)
    cols = amp_cols if use_amp else ("peak_positive [m/s^2]", "peak_negative [m/s^2]")
    clearances = sorted({r["clearance [mm]"] for r in rows}, key=lambda c: _float(c) if c else 0.0) or [""]
    fig, axes = plt.subplots(len(clearances), 2, figsize=(11, 3.6 * len(clearances)), squeeze=False,
                             sharex=True)
    lines = sorted({r["line"] for r in rows})
    for i, c in enumerate(clearances):
        for j, (col, direction) in enumerate(zip(cols, ("positive", "negative"))):
            ax = axes[i][j]
            for k, line in enumerate(lines):
                pts = sorted((_float(r["speed [rpm]"]), _float(r[col])) for r in rows
                             if r["clearance [mm]"] == c and r["line"] == line)
                pts = [p for p in pts if math.isfinite(p[1])]
                if pts:
                    ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", ms=3, lw=1, color="C%d" % (k % 10),
                            label=line)
            title = ("clearance %s mm, " % c if c else "") + direction + " direction"
            ax.set_title(title, fontsize=10)
            ax.set_ylabel("amplification factor [-]" if use_amp else "peak |slider acceleration| [m/s^2]")
            ax.grid(True, alpha=0.3)
            if i == len(clearances) - 1:
                ax.set_xlabel("crank speed [rpm]")
    handles, labels = axes[0][0].get_legend_handles_labels()
    if handles:
        fig.legend(handles, labels, loc="upper center", ncol=min(len(labels), 4), fontsize=8)
    fig.tight_layout(rect=(0, 0, 1, 0.93 if handles else 1))
    save(fig, out_png)


def plot_compare(directory, max_points=20000):
    """For every comparison_NN_points.csv in DIR: a 3-D scatter (speed x crank angle x
    acceleration, one colour per rod) and its plan view (speed x crank angle)."""
    from mpl_toolkits.mplot3d import Axes3D  # noqa: F401  (registers the 3-D projection)
    for name in sorted(os.listdir(directory)):
        if not (name.startswith("comparison_") and name.endswith("_points.csv")):
            continue
        stem = os.path.join(directory, name[: -len("_points.csv")])
        with open(os.path.join(directory, name), newline="") as f:
            rows = list(csv.DictReader(f))
        if not rows:
            continue
        title = os.path.basename(stem)
        md = stem + ".md"
        if os.path.exists(md):
            with open(md) as f:
                title = f.readline().lstrip("# ").strip()
        items = []
        for r in rows:
            if r["item"] not in items:
                items.append(r["item"])
        fig3 = plt.figure(figsize=(8, 6.5))
        ax3 = fig3.add_subplot(projection="3d")
        fig2, ax2 = plt.subplots(figsize=(8, 5))
        for k, item in enumerate(items):
            pts = [r for r in rows if r["item"] == item]
            step = max(1, len(pts) // max_points)  # deterministic thinning for very large sweeps
            pts = pts[::step]
            speed = [float(r["speed [rpm]"]) for r in pts]
            angle = [float(r["crank_angle [deg]"]) for r in pts]
            acc = [float(r["acceleration [m/s^2]"]) for r in pts]
            ax3.scatter(speed, angle, acc, s=2, color="C%d" % (k % 10), label=item, depthshade=False)
            peak = max([abs(a) for a in acc] + [1e-300])
            sizes = [2.0 + 30.0 * abs(a) / peak for a in acc]  # marker area grows with |acceleration|
            ax2.scatter(angle, speed, s=sizes, color="C%d" % (k % 10), label=item, alpha=0.5)
        ax3.set_xlabel("crank speed [rpm]")
        ax3.set_ylabel("crank angle [deg]")
        ax3.set_zlabel("slider acceleration [m/s^2]")
        ax3.set_title(title, fontsize=9)
        ax3.legend(markerscale=4, fontsize=8)
        ax2.set_xlabel("crank angle [deg]")
        ax2.set_ylabel("crank speed [rpm]")
        ax2.set_xlim(0, 360)
        ax2.set_title(title + " (plan view; marker size ~ |acceleration|)", fontsize=9)
        ax2.legend(markerscale=4, fontsize=8)
        ax2.grid(True, alpha=0.3)
        save(fig3, stem + "_scatter.png")
        save(fig2, stem + "_plan.png")


def plot_spectrum_and_poincare(directory, cols):
    """Amplitude spectrum and Poincare map of the slider acceleration."""
    t = np.asarray(cols["time [s]"])
    acc = np.asarray(cols["slider_acceleration [m/s^2]"])
    theta = np.asarray(cols["crank_angle [rad]"])
    rate = (len(t) - 1) / (t[-1] - t[0]) if len(t) > 1 else 1.0
    stored = stored_spectrum(directory)
    if stored is not None:  # the summary's spectrum (run.h5)
        freq, amp, window = stored
    else:  # Hann window, amplitude-corrected (a sine of amplitude A reads A)
        w = np.hanning(len(acc))
        amp = 2.0 * np.abs(np.fft.rfft(acc * w)) / w.sum()
        freq = np.fft.rfftfreq(len(acc), 1.0 / rate)
        window = "hann"
    fig, ax = plt.subplots(figsize=(9, 4.5))
    ax.semilogy(freq[1:], amp[1:], lw=0.6)
    ax.set_xlim(0, min(freq[-1], 5000.0))
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("amplitude of slider acceleration [m/s^2] (%s window)" % window)
    ax.grid(True, alpha=0.3)
    save(fig, os.path.join(directory, "spectrum.png"))
    # Poincare map: one point per revolution where the crank passes the index angle (0).
    k = np.floor(theta / (2 * np.pi))
    idx = np.nonzero(np.diff(k) > 0)[0] + 1
    if len(idx) > 0:
        fig, ax = plt.subplots(figsize=(6, 4.5))
        if "journal_eccentricity_x [m]" in cols and "journal_eccentricity_y [m]" in cols:
            e = np.hypot(cols["journal_eccentricity_x [m]"], cols["journal_eccentricity_y [m]"])
            ax.plot(1e3 * e[idx], acc[idx], "o", ms=3)
            ax.set_xlabel("journal eccentricity at the index [mm]")
        else:
            ax.plot(np.arange(len(idx)), acc[idx], "o", ms=3)
            ax.set_xlabel("revolution")
        ax.set_ylabel("slider acceleration at the index [m/s^2]")
        ax.grid(True, alpha=0.3)
        save(fig, os.path.join(directory, "poincare.png"))


def plot_orbit_and_bearing_force(directory, cols):
    """Journal centre orbit in the clearance circle; bearing force against crank angle."""
    if "journal_eccentricity_x [m]" in cols and "journal_eccentricity_y [m]" in cols:
        ex = 1e3 * np.asarray(cols["journal_eccentricity_x [m]"])
        ey = 1e3 * np.asarray(cols["journal_eccentricity_y [m]"])
        c = clearance_mm(directory)
        fig, ax = plt.subplots(figsize=(5.5, 5.5))
        if c:
            phi = np.linspace(0, 2 * np.pi, 361)
            ax.plot(c * np.cos(phi), c * np.sin(phi), "k-", lw=0.8, label="clearance circle")
        # Every pixel the journal centre visited (a 600 x 600 occupancy image), not 10^5 segments.
        lim = max(c or 0.0, np.abs(ex).max(), np.abs(ey).max()) * 1.05 or 1.0
        hist, _, _ = np.histogram2d(ey, ex, bins=600, range=[[-lim, lim], [-lim, lim]])
        ax.imshow(np.where(hist > 0, 1.0, np.nan), extent=(-lim, lim, -lim, lim), origin="lower",
                  cmap="Blues", vmin=0.0, vmax=1.2, interpolation="nearest")
        ax.plot([], [], color="C0", label="journal centre (pixels visited)")
        ax.set_aspect("equal")
        ax.set_xlabel("eccentricity x [mm]")
        ax.set_ylabel("eccentricity y [mm]")
        ax.legend(loc="upper right", fontsize=8)
        save(fig, os.path.join(directory, "journal_orbit.png"))
    if "bearing_force [N]" in cols:  # |force on the bush|: ideal reaction or contact force
        force = np.asarray(cols["bearing_force [N]"])
        fig, ax = plt.subplots(figsize=(9, 4.5))
        theta = np.asarray(cols["crank_angle [rad]"])
        envelope(ax, np.degrees(np.mod(theta, 2 * np.pi)), force, 0, 360, "C0")
        ax.set_xlim(0, 360)
        ax.set_xlabel("crank angle [deg]")
        ax.set_ylabel("small-end bearing force [N]")
        ax.grid(True, alpha=0.3)
        save(fig, os.path.join(directory, "bearing_force.png"))


def clearance_mm(directory):
    path = os.path.join(directory, "resolved.toml")
    if not os.path.exists(path):
        return None
    section = ""
    for line in open(path):
        line = line.split("#")[0].strip()
        if line.startswith("["):
            section = line.strip("[]")
        elif section == "joint" and line.startswith("clearance"):
            return 1e3 * float(line.split("=")[1])
    return None


def plot_study(directory):
    """Bar plot of the peak slider acceleration of every case in DIR/table.csv, beside the median
    over revolutions of each revolution's peak (the trend statistic). (Each case's directory
    holds its own plots, the slider acceleration against the ideal twin among them.)"""
    with open(os.path.join(directory, "table.csv"), newline="") as f:
        rows = list(csv.reader(f))
    header, rows = rows[0], rows[1:]
    labels = [r[0] + " / " + r[1] for r in rows]

    def column(name):
        c = header.index(name)
        return [float(r[c]) if r[c] not in ("n/a", "") else float("nan") for r in rows]

    peaks = column("peak abs slider acc. [m/s^2]")
    medians = column("median per-rev. peak abs slider acc. [m/s^2]")
    fig, ax = plt.subplots(figsize=(max(6, 0.45 * len(rows)), 4.5))
    x = list(range(len(rows)))
    ax.bar([i - 0.2 for i in x], peaks, width=0.4, color="C0", label="peak")
    ax.bar([i + 0.2 for i in x], medians, width=0.4, color="C1", label="median of per-revolution peaks")
    ax.legend(fontsize=8)
    ax.set_xticks(x)
    ax.set_xticklabels(labels, rotation=70, ha="right", fontsize=8)
    ax.set_ylabel("peak |slider acceleration| [m/s^2]")
    ax.set_yscale("log")
    ax.grid(True, axis="y", alpha=0.3)
    fig.tight_layout()
    save(fig, os.path.join(directory, "peaks.png"))


def plot_reduction(directory):
    """Convergence of the modal reduction study (DIR/table.csv): |difference to the exact rod| of
    every figure against the Craig-Bampton mode count k, with the full FE model as a line."""
    with open(os.path.join(directory, "table.csv"), newline="") as f:
        rows = list(csv.reader(f))
    header, rows = rows[0], rows[1:]
    figures = [header[i] for i in range(2, len(header) - 2, 2)]
    cb = [r for r in rows if r[0].startswith("cb-")]
    ks = [int(r[0][3:]) for r in cb]

    def diff(row, fig):
        v = row[header.index(fig) + 1]
        return abs(float(v)) if v not in ("n/a", "") else float("nan")

    fig, ax = plt.subplots(figsize=(7, 4.5))
    for i, name in enumerate(figures):
        ys = [max(diff(r, name), 1e-4) for r in cb]
        ax.plot(ks, ys, "o-", color="C%d" % i, label=name)
        full = [r for r in rows if r[0] == "full"]
        if full and not math.isnan(diff(full[0], name)):
            ax.axhline(max(diff(full[0], name), 1e-4), color="C%d" % i, ls=":", lw=0.8)
    ax.set_xscale("symlog", linthresh=1)
    ax.set_yscale("log")
    ax.set_xlabel("Craig-Bampton fixed-interface modes k")
    ax.set_ylabel("|difference to the exact rod| [%] (dotted: full FE)")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    save(fig, os.path.join(directory, "convergence.png"))


def plot_damping(directory):
    """The damping study (DIR/table.csv): each headline figure under each damping model, its
    ensemble centre with the 95 % interval as an error bar, one panel per figure."""
    with open(os.path.join(directory, "table.csv"), newline="") as f:
        rows = list(csv.reader(f))
    header, rows = rows[0], rows[1:]
    figures = [header[i] for i in range(3, len(header), 3)]
    fig, axes = plt.subplots(1, len(figures), figsize=(3.2 * len(figures), 3.8))
    names = [r[0] for r in rows]
    for ax, name in zip(np.atleast_1d(axes), figures):
        col = header.index(name)
        xs, ys, lo, hi = [], [], [], []
        for i, r in enumerate(rows):
            if r[col] in ("-", "") or ".." not in r[col + 1]:
                continue
            a, b = (float(v) for v in r[col + 1].split(".."))
            xs.append(i)
            ys.append(float(r[col]))
            lo.append(float(r[col]) - a)
            hi.append(b - float(r[col]))
        ax.errorbar(xs, ys, yerr=[lo, hi], fmt="o", capsize=3)
        ax.set_xticks(range(len(names)))
        ax.set_xticklabels(names, rotation=45, ha="right", fontsize=7)
        ax.set_title(name, fontsize=8)
        ax.grid(True, alpha=0.3)
    fig.tight_layout()
    save(fig, os.path.join(directory, "damping.png"))


def main(argv):
    if len(argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    if argv[1] == "run":
        # --wait: started before the run's files exist (the imports overlap the simulation);
        # plots when "go" arrives on stdin, exits without plotting on anything else.
        if "--wait" in argv[3:] and sys.stdin.readline().strip() != "go":
            return 0
        plot_run(argv[2])
        return 0
    if argv[1] == "study":
        plot_study(argv[2])
        return 0
    if argv[1] == "reduction":
        plot_reduction(argv[2])
        return 0
    if argv[1] == "damping":
        plot_damping(argv[2])
        return 0
    if argv[1] == "sweep" and len(argv) >= 4:
        plot_sweep(argv[2], argv[3])
        return 0
    if argv[1] == "compare":
        plot_compare(argv[2])
        return 0
    print("unknown plot kind: " + argv[1], file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
