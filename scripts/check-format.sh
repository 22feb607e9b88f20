#!/usr/bin/env bash
# Every C++ source of the repository is clang-format clean (Debian's clang-format, the project's
# .clang-format). Lists the files that are not and exits 1; `scripts/check-format.sh --fix`
# formats them in place. Run by ctest (format.clang_format) and so by .ci/run.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  mapfile -t files < <(git ls-files '*.cc' '*.h')
else
  mapfile -t files < <(find . -path ./build\* -prune -o \( -name '*.cc' -o -name '*.h' \) -print)
fi
bad=()
for f in "${files[@]}"; do
  [ -f "$f" ] || continue
  if ! clang-format --dry-run -Werror "$f" >/dev/null 2>&1; then
    if [ "${1:-}" = "--fix" ]; then clang-format -i "$f"; else bad+=("$f"); fi
  fi
done
if [ ${#bad[@]} -gt 0 ]; then
  printf 'not clang-format clean (scripts/check-format.sh --fix formats them):\n'
  printf '  %s\n' "${bad[@]}"
  exit 1
fi
echo "${#files[@]} files clang-format clean"
