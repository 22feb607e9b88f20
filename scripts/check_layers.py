#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The layers of flexrod, checked on every #include "..." of the sources.

Data flows upwards; a folder may include only itself and the layers below it:

  common                    (nothing else)
  fem, contact              common
  multibody                 common, fem, contact
  study: signal analysis    common and the signal analysis itself
         (study/signals*, study/timeseries*: time series only, never the solver)
  study: the rest           common, fem, contact, multibody, study
  app                       everything above but python/, tests/, benchmarks/
  python                    common, fem, contact, multibody, study (never app/)

A header that says "Internal to <folder>/" or "Not for use outside <folder>/" in its first
lines may be included only from that folder.

Usage: check_layers.py [ROOT]       exit 1 listing every include against the direction
       check_layers.py --selftest   proves on a scratch tree that a forbidden include fails
Run by the build (target layers, before any library compiles) and by ctest (layers.includes,
layers.selftest). Standard library only.
"""
import pathlib
import re
import sys
import tempfile

LIBRARIES = ("common", "fem", "contact", "multibody", "study")
ALLOWED = {
    "common": {"common"},
    "fem": {"common", "fem"},
    "contact": {"common", "contact"},
    "multibody": {"common", "fem", "contact", "multibody"},
    "study": {"common", "fem", "contact", "multibody", "study"},
    "app": set(LIBRARIES) | {"app"},
    "python": set(LIBRARIES) | {"python"},
}
SIGNALS = re.compile(r"^study/(signals[a-z_]*|timeseries)\.(h|cc)$")
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
INTERNAL = re.compile(r"(?:Internal to|Not for use outside) ([a-z_]+)/")


def internal_headers(root):
    """{header path: the folder it is internal to}, from the marker in its first 5 lines."""
    out = {}
    for path in root.glob("*/*.h"):
        head = "\n".join(path.read_text(encoding="utf-8", errors="replace").splitlines()[:5])
        m = INTERNAL.search(head)
        if m:
            out[path.relative_to(root).as_posix()] = m.group(1)
    return out


def violations(root):
    root = pathlib.Path(root)
    found = []
    internal = internal_headers(root)
    for folder, allowed in ALLOWED.items():
        for path in sorted((root / folder).rglob("*")):
            if path.suffix not in (".h", ".cc"):
                continue
            rel = path.relative_to(root).as_posix()
            signals = SIGNALS.match(rel) is not None
            for target in INCLUDE.findall(path.read_text(encoding="utf-8", errors="replace")):
                top = target.split("/")[0]
                if "/" not in target:
                    continue  # a header beside it (python/ bindings) or a system-style name
                if target in internal and internal[target] != folder:
                    found.append("%s includes %s: that header is internal to %s/" % (
                        rel, target, internal[target]))
                    continue
                if signals:
                    ok = top == "common" or SIGNALS.match(target) is not None
                else:
                    ok = top in allowed
                if not ok:
                    found.append("%s includes %s: %s may include only %s" % (
                        rel, target, "study's signal analysis" if signals else folder + "/",
                        "common/ and study/signals*, study/timeseries*" if signals
                        else ", ".join(sorted(allowed))))
    return found


def selftest():
    """A tree with one include against each rule kind must fail; the same tree without them
    must pass."""
    with tempfile.TemporaryDirectory() as tmp:
        root = pathlib.Path(tmp)
        files = {
            "common/a.h": '#include "common/b.h"\n',
            "fem/beam.cc": '#include "common/a.h"\n#include "multibody/dae.h"\n',
            "study/signals.cc": '#include "study/timeseries.h"\n#include "multibody/simulate.h"\n',
            "study/run.cc": '#include "multibody/simulate.h"\n#include "app/commands.h"\n',
            "python/module.cc": '#include "study/run.h"\n#include "app/cli.h"\n',
            "multibody/kernels.h": "// multibody/kernels.h — Internal to multibody/.\n",
            "multibody/dae.cc": '#include "multibody/kernels.h"\n',
            "study/run_setup.cc": '#include "multibody/dae.h"\n#include "multibody/kernels.h"\n',
        }
        for name, text in files.items():
            (root / name).parent.mkdir(parents=True, exist_ok=True)
            (root / name).write_text(text)
        bad = violations(root)
        expected = ["fem/beam.cc includes multibody/dae.h",
                    "study/signals.cc includes multibody/simulate.h",
                    "study/run.cc includes app/commands.h",
                    "python/module.cc includes app/cli.h",
                    "study/run_setup.cc includes multibody/kernels.h"]
        for e in expected:
            if not any(v.startswith(e) for v in bad):
                print("selftest: not caught: " + e)
                return 1
        if len(bad) != len(expected):
            print("selftest: caught too much: %s" % bad)
            return 1
        for name in files:  # remove the forbidden lines: clean
            p = root / name
            p.write_text("".join(l + "\n" for l in p.read_text().splitlines()[:1]))
        if violations(root):
            print("selftest: a clean tree fails: %s" % violations(root))
            return 1
    print("selftest: every forbidden include is caught, a clean tree passes")
    return 0


def main(argv):
    if len(argv) > 1 and argv[1] == "--selftest":
        return selftest()
    root = argv[1] if len(argv) > 1 else pathlib.Path(__file__).resolve().parents[1]
    bad = violations(root)
    for v in bad:
        print(v)
    print("%d includes against the layers" % len(bad))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
