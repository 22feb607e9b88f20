#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""README figures that cannot go stale: reruns the main job (`flexrod run`, the README's first
command's job) and compares its report with the block the README prints, line by line, every
number to the printed digits; wall times are the only numbers left out (they vary with the
machine), and the output size is checked within 5 %.

  readme_main_job.py FLEXROD_BINARY README.md        exit 0 if the README matches
"""
import os
import re
import subprocess
import sys
import tempfile

NUMBER = re.compile(r"[-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?")


def readme_block(readme):
    """The lines of the code block that follows "It prints:" in the README."""
    text = open(readme, encoding="utf-8").read()
    start = text.index("```", text.index("It prints:")) + 3
    end = text.index("```", start)
    return [line for line in text[start:end].splitlines() if line.strip()]


def main(argv):
    binary, readme = argv[1], argv[2]
    expected = readme_block(readme)
    with tempfile.TemporaryDirectory() as tmp:
        proc = subprocess.run([binary, "run", "--no-plot", "--out", os.path.join(tmp, "run")],
                              capture_output=True, text=True, timeout=600)
    if proc.returncode != 0:
        print(proc.stderr)
        return 1
    actual = [line for line in proc.stdout.splitlines() if line.strip()]
    actual[0] = actual[0].replace(os.path.join(tmp, "run"), "out/run")
    errors = []
    if len(actual) != len(expected):
        errors.append("%d lines printed, the README has %d" % (len(actual), len(expected)))
    for e, a in zip(expected, actual):
        if "wall" in e:  # the integrator line: its counts must match, its wall time not
            e, a = e.split("wall")[0], a.split("wall")[0]
        if e.strip().startswith("files:"):
            size_e, size_a = float(NUMBER.findall(e)[0]), float(NUMBER.findall(a)[0])
            if abs(size_a - size_e) > 0.05 * size_e:
                errors.append("output size %s MB, the README says %s MB" % (size_a, size_e))
            continue
        if e != a:
            errors.append("README: %s\n  run:    %s" % (e, a))
    for err in errors:
        print(err)
    print("%d of %d lines differ" % (len(errors), len(expected)))
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
