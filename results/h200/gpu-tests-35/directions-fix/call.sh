#!/bin/bash
# Session 35, call 8: the LDM directions' fix (N = 30808e6) per pass against M (e1df798, the
# directions before it), on the passes that read ldmDirections: indirect-cut.json (raytraced split
# photons, 512 directions, 800x800), twice interleaved, and ldm-cut.json (LDM AO 512 x 200^2,
# hardware and 3dr builds, and ray-traced AO 512 at 800x800), N, M, N. Warmed by peaks.
set -u
cd "$(dirname "$0")"
tar xf hb56.tar.xz -C /tmp
tar xf hb65.tar.xz -C /tmp
B=/tmp/hbx
mkdir -p "$OUT/r" /tmp/o8
nvidia-smi > "$OUT/nvidia-smi.txt"
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > /tmp/o8/$name.log 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> "$OUT/times.txt"; [ -f /tmp/o8/$name/results.json ] && gzip -9c /tmp/o8/$name/results.json > "$OUT/r/$name.results.json.gz"; }
run 60 warm $B/M/hybridbench peaks --json
for rep in 1 2; do for b in M N35; do run 60 ind-$b-$rep $B/$b/hybridbench sweep indirect-cut.json --out /tmp/o8/ind-$b-$rep --no-images; done; done
run 100 ldm-N35-1 $B/N35/hybridbench sweep ldm-cut.json --out /tmp/o8/ldm-N35-1 --no-images
run 100 ldm-M-1 $B/M/hybridbench sweep ldm-cut.json --out /tmp/o8/ldm-M-1 --no-images
run 100 ldm-N35-2 $B/N35/hybridbench sweep ldm-cut.json --out /tmp/o8/ldm-N35-2 --no-images
echo "total $(( $(date +%s)-T0 )) s" >> "$OUT/times.txt"
