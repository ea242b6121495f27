#!/usr/bin/env bash
# The C++ tree follows .clang-format (clang-format 14, from Debian's clang-format package).
#   scripts/format.sh           rewrite every tracked C++ file in place
#   scripts/format.sh --check   list the files that differ and exit 1 (CI runs this); fix with scripts/format.sh
set -euo pipefail
cd "$(dirname "$0")/.."
command -v clang-format >/dev/null || { echo "format.sh: clang-format not found; run scripts/setup.sh (Debian package clang-format)" >&2; exit 2; }
mapfile -t files < <(git ls-files 'src/*.cpp' 'src/*.h' 'tests/*.cpp' 'tests/*.h' 'shaders/shared/*.h')
if [ "${1:-}" = --check ]; then
  if ! clang-format --dry-run -Werror "${files[@]}" 2>/tmp/format-check.$$; then
    grep -o '^[^:]*:[0-9]*:[0-9]*: error' /tmp/format-check.$$ | cut -d: -f1 | sort -u | sed 's/^/format.sh: not formatted: /' >&2
    rm -f /tmp/format-check.$$
    echo "format.sh: run scripts/format.sh to format them (.clang-format)" >&2
    exit 1
  fi
  rm -f /tmp/format-check.$$
  echo "format.sh: ${#files[@]} files follow .clang-format"
else
  clang-format -i "${files[@]}"
fi
