#!/usr/bin/env bash
# Code written twice outside results/ (issue #50's count): the pairs of places that share 6 or more
# lines, the same or of the same shape, as the `duplicates` command lists them. results/ holds
# generated pages that repeat each other by design and fill the command's 200 rows, so the tree is
# copied without it (the files git tracks and the untracked ones it does not ignore, as they are in
# the working tree) and every pair is listed. Prints the rows, then a line with the count of pairs
# and of identical ones (rows without "shape"). Run from anywhere in the checkout:
#   tools/duplicates_outside_results.sh [--seconds N]
set -euo pipefail
command -v duplicates >/dev/null || { echo "duplicates_outside_results: no 'duplicates' command in PATH" >&2; exit 2; }
root="$(git rev-parse --show-toplevel)"
copy="$(mktemp -d)"
trap 'rm -rf "$copy"' EXIT
git -C "$root" ls-files -z --cached --others --exclude-standard -- . ':!results' |
  (cd "$root" && tar --null --files-from=- --ignore-failed-read -cf - 2>/dev/null) | tar -xf - -C "$copy"
args=("$@")
[ $# -gt 0 ] || args=(--seconds 150)
rows="$(duplicates --repo "$copy" --most 200 "${args[@]}" | sed "s#$copy/##g")"
printf '%s\n' "$rows"
pairs="$(grep -cE '^D[0-9]' <<<"$rows" || true)"
identical="$(grep -E '^D[0-9]' <<<"$rows" | grep -vc ' shape' || true)"
echo "outside results/: $pairs pairs, $identical identical"
