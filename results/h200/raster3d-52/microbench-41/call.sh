#!/bin/bash
# Session 41, call 4: the paper's microbenchmark (mb-cut.json: 262,144 large random triangles at
# 1920x1080, the hardware prepass, 3dr-binned and the best frame's 3dr-binned) with the tight box
# (F, df56928). Warmed by peaks.
set -u
cd "$(dirname "$0")"
tar xf hb41d.tar.xz -C /tmp
B=/tmp/hbx
mkdir -p /tmp/r
nvidia-smi > /tmp/r/nvidia-smi.txt
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > /tmp/r/$name.log 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> /tmp/r/times.txt; }
run 60 warm $B/F/hybridbench peaks --json
run 120 mb $B/F/hybridbench sweep mb-cut.json --out /tmp/r/mb --no-images
echo "total $(( $(date +%s)-T0 )) s" >> /tmp/r/times.txt
cp /tmp/r/times.txt "$OUT/"
for d in /tmp/r/*/; do rm -rf "$d"/images "$d"/*.png "$d"/*.exr "$d"/*.html 2>/dev/null; done
tar cJf "$OUT/r.tar.xz" -C /tmp r
