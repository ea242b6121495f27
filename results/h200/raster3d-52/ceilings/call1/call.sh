#!/bin/bash
# Session 37, call 1: N = main 07461c7 + the measured ceilings (tile_loop_steps, splat_tests,
# microbench-dense, configs/ceilings*.json). Warmed by peaks; the atrium's aa-cut and the ceiling
# config twice, interleaved; then the splat's ceiling config and the K = 3 target cut once.
set -u
cd "$(dirname "$0")"
tar xf hb37.tar.xz -C /tmp
B=/tmp/hbx
mkdir -p /tmp/r
nvidia-smi > /tmp/r/nvidia-smi.txt
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > /tmp/r/$name.log 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> /tmp/r/times.txt; }
run 60 warm $B/N/hybridbench peaks --json
for rep in 1 2; do
  run 120 aa-N-$rep $B/N/hybridbench sweep aa-cut.json --out /tmp/r/aa-N-$rep --no-images
  run 200 ceil-N-$rep $B/N/hybridbench sweep ../configs/ceilings.json --out /tmp/r/ceil-N-$rep --no-images
done
run 200 splat-ceil $B/N/hybridbench sweep ../configs/ceilings-splat.json --out /tmp/r/splat-ceil --no-images
run 150 stride-cut $B/N/hybridbench sweep stride-cut.json --out /tmp/r/stride-cut --no-images
echo "total $(( $(date +%s)-T0 )) s" >> /tmp/r/times.txt
cp /tmp/r/times.txt "$OUT/"
for d in /tmp/r/*/; do rm -rf "$d"/images "$d"/*.png "$d"/*.exr 2>/dev/null; done
tar cJf "$OUT/r.tar.xz" -C /tmp r
