#!/bin/bash
# The tile pass's fast path in the per-triangle pass's in-place loop (F) against main before it
# (A, 73d9924). Warm with peaks; aa-cut (the best frame's 3dr-binned, none and MSAA 16, atrium
# 1080p) A F A F; 3dr-cut (eleven variants of configs/3d-rasterization.json, 100 measured frames)
# A F.
set -u
cd "$(dirname "$0")"
tar xf hb42c.tar.xz -C /tmp
B=/tmp/hbx
mkdir -p /tmp/r
nvidia-smi > /tmp/r/nvidia-smi.txt
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > /tmp/r/$name.log 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> /tmp/r/times.txt; }
run 60 warm $B/F/hybridbench peaks --json
for i in 1 2; do
  for b in A F; do run 100 aa-$b-$i $B/$b/hybridbench sweep aa-cut.json --out /tmp/r/aa-$b-$i --no-images; done
done
for b in A F; do run 170 r3d-$b $B/$b/hybridbench sweep 3dr-cut.json --out /tmp/r/r3d-$b --no-images; done
echo "total $(( $(date +%s)-T0 )) s" >> /tmp/r/times.txt
cp /tmp/r/times.txt "$OUT/"
for d in /tmp/r/*/; do rm -rf "$d"/images "$d"/*.png "$d"/*.exr "$d"/*.html 2>/dev/null; done
tar cJf "$OUT/r.tar.xz" -C /tmp r
