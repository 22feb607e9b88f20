#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The modal reduction study (`flexrod study reduction`) from Python: every variant of the
rod (the exact rod as reference, the full FE model, Craig-Bampton k = 0..16, the other bases
at 8 modes) on one case, each figure's difference to the exact rod, and the convergence plot
that the CLI draws (scripts/flexrod_plots.py, from the same table.csv).

    PYTHONPATH=build/python /usr/bin/python3 examples/python/reduction_convergence.py [--quick]
        [--out DIR] [--set key=value ...]

Writes DIR/table.csv and DIR/convergence.png (default out/python/reduction).
--quick (or FLEXROD_EXAMPLE_QUICK=1): a short capture at 20 kHz, for the test suite. The
full case is the flexible rig (about 3 minutes; the README's comparison adds
--set damping.type=rayleigh --set damping.beta=2e-5).
"""

import argparse
import csv
import math
import os
import sys
import time

import flexrod

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "scripts"))
import flexrod_plots  # noqa: E402  (the CLI's plots: the same convergence figure)


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true",
                   default=os.environ.get("FLEXROD_EXAMPLE_QUICK") == "1")
    p.add_argument("--out", default="out/python/reduction")
    p.add_argument("--input", default="flexible-rig")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    args = p.parse_args(argv)

    case = {"sim.settle": "0.1 s", "sim.capture": "0.2 s", "sim.sample_rate": "20 kHz"} \
        if args.quick else {}
    case.update(dict(s.split("=", 1) for s in args.set))

    names, results = None, []
    for v in flexrod.reduction_variants():
        t0 = time.monotonic()
        try:
            r = flexrod.run(args.input, set={**case, **v["set"]})
            outcome = "completed"
        except flexrod.NumericalError as e:  # keep the partial run's figures, as the CLI does
            r, outcome = e.run, e.outcome
        wall = time.monotonic() - t0
        figures = flexrod.reduction_figures(r)
        names = list(figures)
        results.append((v["name"], outcome, list(figures.values()), wall))
        print(f"{v['name']:18s} {outcome:12s} {wall:6.2f} s", flush=True)

    reference = results[0][2]  # the exact rod
    header = ["variant", "outcome"]
    for n in names:
        header += [n, "diff. to exact [%]"]
    header += ["max |diff.| [%]", "wall [s]"]
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "table.csv"), "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(header)
        for name, outcome, values, wall in results:
            row, worst = [name, outcome], 0.0
            for v, e in zip(values, reference):
                ok = math.isfinite(v) and math.isfinite(e) and e != 0.0
                diff = 100.0 * (v - e) / abs(e) if ok else math.nan
                worst = max(worst, abs(diff)) if ok else worst
                row += [f"{v:.4g}" if math.isfinite(v) else "n/a",
                        f"{diff:.4g}" if ok else "n/a"]
            w.writerow(row + [f"{worst:.4g}", f"{wall:.4g}"])
    flexrod_plots.plot_reduction(args.out)
    print(f"table: {os.path.join(args.out, 'table.csv')}\n"
          f"plot: {os.path.join(args.out, 'convergence.png')}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
