#!/usr/bin/env bash
# Fuzzes the input parsers (fuzz/parsers_fuzzer.cc: input TOML, sweep matrices, --set) with
# libFuzzer and Debian's clang, under AddressSanitizer + UndefinedBehaviorSanitizer.
# Usage: scripts/fuzz.sh [seconds, default 60]   (.ci/run runs 60 s; longer runs find more)
# Builds into build-fuzz/ (FLEXROD_FUZZ_BUILD_DIR overrides it); the corpus grows in
# build-fuzz/corpus from the seeds in fuzz/corpus. A finding (crash, sanitizer report, an
# exception other than InputError, a hang over 10 s) exits non-zero and leaves its input as
# build-fuzz/crash-* (rerun: build-fuzz/parsers_fuzzer FILE). Compiled with -DNDEBUG like the
# release build; fuzz/ubsan_ignore.txt lists what is left out and why (toml++'s own findings).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds="${1:-60}"
bash "$root/scripts/install-deps.sh"
dir="${FLEXROD_FUZZ_BUILD_DIR:-$root/build-fuzz}"
mkdir -p "$dir/corpus"
cmake -DFLEXROD_SOURCE="$root" -DFLEXROD_OUTPUT="$dir/presets_data.cc" \
  -P "$root/cmake/EmbedPresets.cmake"
# The parsers' sources, derived from the fuzzer's includes (a file split cannot break the list).
mapfile -t sources < <(/usr/bin/python3 "$root/scripts/fuzz_sources.py" "$root")
echo "fuzz: building $dir/parsers_fuzzer (clang++ -fsanitize=fuzzer,address,undefined)"
# One object per source, compiled in parallel (one clang++ over all of them runs on one core).
flags=(-std=c++20 -O1 -g -DNDEBUG -fno-omit-frame-pointer
  -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined
  -fsanitize-ignorelist="$root/fuzz/ubsan_ignore.txt" -I "$root" -I /usr/include/eigen3)
rm -rf "$dir/obj" && mkdir -p "$dir/obj"
export dir
printf '%s\n' "${sources[@]}" "$dir/presets_data.cc" |
  (cd "$root" && xargs -P "$(nproc 2>/dev/null || echo 2)" -I{} sh -c \
    'f="$1"; shift; clang++ "$@" -c "$f" -o "$dir/obj/$(printf %s "$f" | tr / _).o"' \
    sh {} "${flags[@]}")
clang++ -fsanitize=fuzzer,address,undefined "$dir"/obj/*.o -ltomlplusplus -lgsl -lgslcblas \
  -o "$dir/parsers_fuzzer"
echo "fuzz: running for $seconds s"
cd "$dir"
./parsers_fuzzer -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
  -print_final_stats=1 -artifact_prefix="$dir/" corpus "$root/fuzz/corpus"
