#!/usr/bin/env bash
# ctest GltfValidator.EveryExportedAndCommittedSceneHasNoErrorsOrWarnings: the Khronos glTF
# Validator (scripts/validate-gltf.mjs) on every scene the exporter writes and every file in
# scenes/: 0 errors and 0 warnings each (infos and hints are printed, not failed).
#   - every built-in scene (hybridbench scene list --json), the ~262k-triangle ones included,
#     exported as .gltf and as .glb;
#   - every .gltf/.glb at the top of scenes/ and in scenes/external/ as committed, and loaded and
#     exported again as .gltf and .glb (the exporter on what the loader makes of a file: node TRS,
#     extras.effects).
# Usage: tests/gltf_validator_test.sh HYBRIDBENCH
# Needs node and the validator in tools/node_modules (scripts/setup.sh installs both); without
# them it fails with one line saying what is missing.
set -euo pipefail
HB="$1"
SRC="$(cd "$(dirname "$0")/.." && pwd)"
if ! command -v node >/dev/null; then
  echo "gltf_validator_test: node is not installed; run scripts/setup.sh (Debian packages nodejs, npm)" >&2
  exit 1
fi
node "$SRC/scripts/validate-gltf.mjs" --check-installed  # one line naming the fix when missing

WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
mapfile -t builtins < <("$HB" scene list --dir "$SRC/scenes" --json |
  node -e 'let s = ""; process.stdin.on("data", (d) => (s += d)).on("end", () =>
             JSON.parse(s).builtin.forEach((b) => console.log(b.name)))')
[ ${#builtins[@]} -gt 0 ] || { echo "gltf_validator_test: scene list named no built-in scene" >&2; exit 1; }

files=()
for name in "${builtins[@]}"; do
  for ext in gltf glb; do
    "$HB" scene export "$name" "$WORK/$name.$ext" >/dev/null
    files+=("$WORK/$name.$ext")
  done
done
shopt -s nullglob nocaseglob
for committed in "$SRC"/scenes/*.gltf "$SRC"/scenes/*.glb "$SRC"/scenes/external/*.glb; do
  stem="$(basename "${committed%.*}")"
  files+=("$committed")
  for ext in gltf glb; do
    "$HB" scene export "$committed" "$WORK/reexported-$stem.$ext" >/dev/null
    files+=("$WORK/reexported-$stem.$ext")
  done
done
node "$SRC/scripts/validate-gltf.mjs" "${files[@]}"
