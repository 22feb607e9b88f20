#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The layers of flexrod, checked on every #include "..." of the sources.

Data flows upwards; a folder may include only itself and the layers below it:

  common       (nothing else)
  fem          common
  contact      common
  multibody    common, fem, contact
  signals      common                      (time series only, never the solver)
  input        common, contact             (the keys, presets and typed options)
  mechanisms   common, fem, contact, multibody, signals, input
  run          ... and mechanisms
  sweep        ... and run
  io           ... and sweep               (the files of a run)
  app          every library
  python       every library, never app/

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

LIBRARIES = ("common", "fem", "contact", "multibody", "signals", "input", "mechanisms", "run",
             "sweep", "io")
_BELOW_MECHANISMS = {"common", "fem", "contact", "multibody", "signals", "input"}
ALLOWED = {
    "common": {"common"},
    "fem": {"common", "fem"},
    "contact": {"common", "contact"},
    "multibody": {"common", "fem", "contact", "multibody"},
    "signals": {"common", "signals"},
    "input": {"common", "contact", "input"},
    "mechanisms": _BELOW_MECHANISMS | {"mechanisms"},
    "run": _BELOW_MECHANISMS | {"mechanisms", "run"},
    "sweep": _BELOW_MECHANISMS | {"mechanisms", "run", "sweep"},
    "io": _BELOW_MECHANISMS | {"mechanisms", "run", "sweep", "io"},
    "app": set(LIBRARIES) | {"app"},
    "python": set(LIBRARIES) | {"python"},
}
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
            for target in INCLUDE.findall(path.read_text(encoding="utf-8", errors="replace")):
                top = target.split("/")[0]
                if "/" not in target:
                    continue  # a header beside it (python/ bindings) or a system-style name
                if target in internal and internal[target] != folder:
                    found.append("%s includes %s: that header is internal to %s/" % (
                        rel, target, internal[target]))
                    continue
                ok = top in allowed
                if not ok:
                        found.append("%s includes %s: %s/ may include only %s" % (
                        rel, target, folder, ", ".join(sorted(allowed))))
    return found


def selftest():
    """A tree with one include against each rule kind must fail; the same tree without them
    must pass."""
    with tempfile.TemporaryDirectory() as tmp:
        root = pathlib.Path(tmp)
        files = {
            "common/a.h": '#include "common/b.h"\n',
            "fem/beam.cc": '#include "common/a.h"\n#include "multibody/dae.h"\n',
            "signals/signals.cc": '#include "signals/timeseries.h"\n#include "multibody/simulate.h"\n',
            "run/run.cc": '#include "multibody/simulate.h"\n#include "app/commands.h"\n',
            "python/module.cc": '#include "run/run.h"\n#include "app/cli.h"\n',
            "multibody/kernels.h": "// multibody/kernels.h — Internal to multibody/.\n",
            "multibody/dae.cc": '#include "multibody/kernels.h"\n',
            "run/run_setup.cc": '#include "multibody/dae.h"\n#include "multibody/kernels.h"\n',
            "sweep/sweep.cc": '#include "run/run.h"\n#include "io/run_writer.h"\n',
            "input/config.cc": '#include "contact/normal_law.h"\n#include "mechanisms/recipe.h"\n',
        }
        for name, text in files.items():
            (root / name).parent.mkdir(parents=True, exist_ok=True)
            (root / name).write_text(text)
        bad = violations(root)
        expected = ["fem/beam.cc includes multibody/dae.h",
                    "signals/signals.cc includes multibody/simulate.h",
                    "run/run.cc includes app/commands.h",
                    "python/module.cc includes app/cli.h",
                    "run/run_setup.cc includes multibody/kernels.h",
                    "sweep/sweep.cc includes io/run_writer.h",
                    "input/config.cc includes mechanisms/recipe.h"]
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
