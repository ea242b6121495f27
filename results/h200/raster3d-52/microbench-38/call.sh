#!/bin/bash
# Session 38, call 8: main at fe2f3e9 (H); warmed by peaks; configs/3d-rasterization-microbench-262144.json
# cut to hardware, 3dr-binned and the best frame's 3dr-binned (issue #52: >= 2x the hardware).
set -u
cd "$(dirname "$0")"
tar xf hb38m.tar.xz -C /tmp
B=/tmp/hbx
cd ..
mkdir -p /tmp/r
nvidia-smi > /tmp/r/nvidia-smi.txt
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > /tmp/r/$name.log 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> /tmp/r/times.txt; }
run 60 warm $B/H/hybridbench peaks --json
run 300 mb $B/H/hybridbench sweep mb-cut.json (bundle/ on the device) --out /tmp/r/mb --no-images
echo "total $(( $(date +%s)-T0 )) s" >> /tmp/r/times.txt
cp /tmp/r/times.txt "$OUT/"
rm -rf /tmp/r/mb/images /tmp/r/mb/*.png /tmp/r/mb/*.html
tar cJf "$OUT/r.tar.xz" -C /tmp r
