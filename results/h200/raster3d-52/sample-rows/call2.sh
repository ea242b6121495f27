#!/bin/bash
# Session 36, call 2: Y (main at b9aebe7, the sample planes' coverage from the centre's rows, and
# the perspective depth's denominator formed from N·d0, N·dx, N·dy, which the tile passes make once
# a triangle and plane) against M (main at 0391103): aa-cut.json interleaved M, Y twice, then
# r3d-cut.json (configs/3d-rasterization.json at 100 frames: every method) M, Y once; warmed first.
set -u
cd "$(dirname "$0")"
tar xf hb36b.tar.xz -C /tmp
B=/tmp/hbx
mkdir -p /tmp/r
nvidia-smi > /tmp/r/nvidia-smi.txt
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > /tmp/r/$name.log 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> /tmp/r/times.txt; }
run 60 warm $B/M/hybridbench peaks --json
for rep in 1 2; do
  for b in M Y; do run 90 aa-$b-$rep $B/$b/hybridbench sweep aa-cut.json --out /tmp/r/aa-$b-$rep --no-images; done
done
for b in M Y; do run 150 r3d-$b $B/$b/hybridbench sweep r3d-cut.json --out /tmp/r/r3d-$b --no-images; done
echo "total $(( $(date +%s)-T0 )) s" >> /tmp/r/times.txt
cp /tmp/r/times.txt "$OUT/"
tar cJf "$OUT/r.tar.xz" -C /tmp r
