#!/usr/bin/env bash
# A performance bisect in one device call: every hybridbench binary in a bundle's bisect/ folder
# (built here from older revisions, named hybridbench-<rev>; scripts/bundle.sh's lib/ serves them
# all) and the bundle's own binary sweep the same config one after another on the same GPU, each
# into OUT/<rev>/. Run it on the GPU machine from the repository root:
#   tools/bisect_on_device.sh BUNDLE CONFIG OUT [SWEEP ARGS...]
# Then compare any two: hybridbench compare OUT/<a>/results.json OUT/<b>/results.json --gate all.
set -uo pipefail
if [ $# -lt 3 ]; then
  echo "usage: tools/bisect_on_device.sh BUNDLE CONFIG OUT [SWEEP ARGS...]" >&2
  exit 2
fi
bundle="$1" config="$2" out="$3"
shift 3
[ -d "$bundle/lib" ] || { echo "bisect: $bundle/lib is missing; run scripts/bundle.sh $bundle first" >&2; exit 2; }
[ -f "$config" ] || { echo "bisect: no config at $config" >&2; exit 2; }
export LD_LIBRARY_PATH="$bundle/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
if [ -z "${VK_DRIVER_FILES:-}${VK_ICD_FILENAMES:-}" ]; then
  for f in /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json /usr/share/vulkan/icd.d/nvidia_icd.json; do
    [ -f "$f" ] && export VK_DRIVER_FILES="$f" && break
  done
fi
mkdir -p "$out"
status=0
for bin in "$bundle"/bisect/hybridbench-* "$bundle/bin/hybridbench"; do
  [ -x "$bin" ] || continue
  rev="${bin##*/hybridbench-}"
  [ "$bin" = "$bundle/bin/hybridbench" ] && rev="head"
  echo "bisect: $rev ($("$bin" --version 2>&1 | head -1))"
  start=$(date +%s)
  if ! "$bin" sweep "$config" --out "$out/$rev" --no-images "$@" > "$out/$rev.log" 2>&1; then
    echo "bisect: $rev failed, see $out/$rev.log" >&2
    tail -3 "$out/$rev.log" >&2
    status=1
  fi
  echo "bisect: $rev took $(( $(date +%s) - start )) s"
done
exit $status
