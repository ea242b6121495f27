#!/bin/bash
# Probes of the per-triangle pass's in-place loop at main (A, 73d9924), in timed frames only
# (analysis frames untouched): QA skips the loop; QA2 runs it without its atomicMin; QA3 decides
# coverage by the float edge values alone (no rounding bound, fp64 fallback or tie rule). Warm
# with peaks; aa-cut A QA QA2 QA3 A.
set -u
cd "$(dirname "$0")"
tar xf hb42b.tar.xz -C /tmp
B=/tmp/hbx
mkdir -p /tmp/r
nvidia-smi > /tmp/r/nvidia-smi.txt
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > /tmp/r/$name.log 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> /tmp/r/times.txt; }
run 60 warm $B/A/hybridbench peaks --json
for b in A QA QA2 QA3; do run 100 aa-$b-1 $B/$b/hybridbench sweep aa-cut.json --out /tmp/r/aa-$b-1 --no-images; done
run 100 aa-A-2 $B/A/hybridbench sweep aa-cut.json --out /tmp/r/aa-A-2 --no-images
echo "total $(( $(date +%s)-T0 )) s" >> /tmp/r/times.txt
cp /tmp/r/times.txt "$OUT/"
for d in /tmp/r/*/; do rm -rf "$d"/images "$d"/*.png "$d"/*.exr "$d"/*.html 2>/dev/null; done
tar cJf "$OUT/r.tar.xz" -C /tmp r
