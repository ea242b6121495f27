#!/usr/bin/env bash
# Rewrites every committed file in scenes/ (see scenes/README.md):
#   - the built-in scenes, exported by hybridbench (all but the two of ~262k triangles, the atrium
#     and microbench-262144, megabytes each, and the ceiling scenes microbench-dense and
#     microbench-tiny; they are built in anyway);
#   - cornell-box.gltf, written by cornell-box.mjs (node).
# Usage: scenes/regenerate.sh [HYBRIDBENCH]   (default: build/hybridbench)
# A test (Scenes.CommittedBuiltinsAreWhatTheExporterWrites) fails when an exported file differs
# from what the exporter writes today: after changing a hard case or the exporter, run this.
set -euo pipefail
HB="$(realpath "${1:-$(dirname "$0")/../build/hybridbench}")"
cd "$(dirname "$0")"
for name in plane depth-step cube grazing grazing-far thin-gap degenerate open-occluder far-origin \
            far-planes microbench-144; do
  "$HB" scene export "$name" "$name.gltf"
done
# As .gltf its base64 buffer would be 236 KB; the binary container keeps it under 200 KB.
"$HB" scene export tiny-triangles tiny-triangles.glb
node cornell-box.mjs
