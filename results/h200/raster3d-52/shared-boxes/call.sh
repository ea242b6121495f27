#!/bin/bash
# The small boxes' pixels shared by the per-triangle pass's workgroup (C) against main before it
# (A, 73d9924), and probes that skip the in-place pixel loop in timed frames (QA: A's, QC: C's;
# analysis frames untouched). Warm with peaks; aa-cut (the best frame's 3dr-binned, none and
# MSAA 16, atrium 1080p) A C QA QC A C; 3dr-cut (eleven variants of configs/3d-rasterization.json,
# 100 measured frames) C, then A if time is left.
set -u
cd "$(dirname "$0")"
tar xf hb42.tar.xz -C /tmp
B=/tmp/hbx
mkdir -p /tmp/r
nvidia-smi > /tmp/r/nvidia-smi.txt
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > /tmp/r/$name.log 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> /tmp/r/times.txt; }
run 60 warm $B/C/hybridbench peaks --json
for b in A C QA QC; do run 100 aa-$b-1 $B/$b/hybridbench sweep aa-cut.json --out /tmp/r/aa-$b-1 --no-images; done
for b in A C; do run 100 aa-$b-2 $B/$b/hybridbench sweep aa-cut.json --out /tmp/r/aa-$b-2 --no-images; done
run 170 r3d-C $B/C/hybridbench sweep 3dr-cut.json --out /tmp/r/r3d-C --no-images
echo "total $(( $(date +%s)-T0 )) s" >> /tmp/r/times.txt
cp /tmp/r/times.txt "$OUT/"
for d in /tmp/r/*/; do rm -rf "$d"/images "$d"/*.png "$d"/*.exr "$d"/*.html 2>/dev/null; done
tar cJf "$OUT/r.tar.xz" -C /tmp r
