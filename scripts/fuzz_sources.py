#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The sources the parser fuzzer links (scripts/fuzz.sh), derived from its includes so that a
file split cannot break it: starting from fuzz/parsers_fuzzer.cc, every project header
folder/x.h it reaches brings the sources that define it (folder/x.cc, folder/x_*.cc, and a
source of that folder whose first include from its own folder is x.h), and their includes in
turn. Prints the list, one path per line, relative to the root.
Usage: fuzz_sources.py ROOT"""
import pathlib
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s+"([a-z0-9_]+/[a-z0-9_]+\.h)"', re.M)


def main(root):
    root = pathlib.Path(root)
    includes, defines = {}, {}
    for cc in root.glob("*/*.cc"):
        rel = cc.relative_to(root).as_posix()
        found = INCLUDE.findall(cc.read_text(encoding="utf-8"))
        includes[rel] = set(found)
        own = [h for h in found if h.split("/")[0] == cc.parent.name]
        defines[rel] = {own[0]} if own else set()
    headers = {h.relative_to(root).as_posix(): set(INCLUDE.findall(h.read_text(encoding="utf-8")))
               for h in root.glob("*/*.h")}
    sources, seen, todo = [], set(), ["fuzz/parsers_fuzzer.cc"]
    while todo:
        f = todo.pop()
        if f in seen:
            continue
        seen.add(f)
        if f.endswith(".cc"):
            sources.append(f)
            todo += sorted(includes.get(f, ()))
        else:
            todo += sorted(headers.get(f, ()))
            stem = f[:-2]
            todo += sorted(cc for cc in includes
                           if cc == stem + ".cc" or cc.startswith(stem + "_") or f in defines[cc])
    print("\n".join(sorted(sources)))


if __name__ == "__main__":
    main(sys.argv[1])
