#!/usr/bin/env bash
# results/ stays light enough to clone (docs/results-format.md "Committed results"): the tracked
# files under results/ total at most 31 MB; no committed JSON of 32 KiB or more is left
# uncompressed, and no reference names a .json that is kept as .json.gz
# (tools/compress_results.py --check); results/README.md, the index, is at most 400 lines.
set -euo pipefail
root=${1:?usage: results_weight_test.sh REPO_ROOT}
cd "$root"
readonly kMaxBytes=31000000 kMaxIndexLines=400
fail=0
bytes=$(git ls-files -z results | xargs -0 stat -c %s | awk '{s += $1} END {print s + 0}')
echo "results/ in the tree: $bytes bytes (limit $kMaxBytes)"
if [ "$bytes" -gt "$kMaxBytes" ]; then
  echo "results/ holds $bytes bytes, over $kMaxBytes: run python3 tools/compress_results.py, or commit smaller previews" >&2
  git ls-files -z results | xargs -0 stat -c '%s %n' | sort -rn | head -5 >&2
  fail=1
fi
python3 tools/compress_results.py --check || fail=1
lines=$(wc -l < results/README.md)
if [ "$lines" -gt "$kMaxIndexLines" ]; then
  echo "results/README.md has $lines lines, over $kMaxIndexLines: it is an index (tools/results_index.py)" >&2
  fail=1
fi
exit $fail
