#!/bin/bash
# Session 40 (#51): octant-ordered children at width 4 (closest hits), an experiment. A: main at
# 25deb97; O1: the first child in the ray octant's stored order is entered, the rest pushed far
# first, no sort; O2: the nearest child is entered, the rest pushed in the octant's order, no sort.
# Warm with peaks; then the issue's three sets and the frame's own rays, A O1 O2 interleaved, twice.
set -u
cd "$(dirname "$0")"
tar xf hb40.tar.xz -C /tmp
B=/tmp/hbx
mkdir -p /tmp/r /tmp/rays /tmp/frame
nvidia-smi > /tmp/r/nvidia-smi.txt
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > /tmp/r/$name.log 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> /tmp/r/times.txt; }
run 60 warm $B/A/hybridbench peaks --json
run 30 export $B/A/hybridbench rays export --scene atrium --size 1920x1080 --out /tmp/rays
for round in 1 2; do
  for s in camera ao shadow; do
    for b in A O1 O2; do run 40 rb-$s-$b-$round $B/$b/hybridbench raybench /tmp/rays/$s.bin --json /tmp/r/raybench-$s-$b-$round.json; done
  done
done
echo "total $(( $(date +%s)-T0 )) s" >> /tmp/r/times.txt
cp /tmp/r/times.txt "$OUT/"
tar cJf "$OUT/r.tar.xz" -C /tmp r
