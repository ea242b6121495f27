#!/bin/bash
# Session 34, call 1 (a 2-GPU H200 host): #53 the thesis with the driver's ray-tracing pipeline swept
# on both GPUs at once, twice: two more A/A pairs of the class "pipeline, swept beside other
# devices" (main at e1df798, bundle M).
set -u
cd "$(dirname "$0")"
tar xf hb56.tar.xz -C /tmp
B=/tmp/hbx
mkdir -p "$OUT/r" /tmp/r
nvidia-smi > "$OUT/nvidia-smi.txt"
$B/M/hybridbench devices > "$OUT/devices.txt" 2>&1
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > "$OUT/r/$name.log" 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> "$OUT/times.txt"; }
for rep in 1 2; do
  run 240 run$rep $B/M/hybridbench sweep ../configs/thesis.json --device all --set backend=pipeline --out /tmp/r/run$rep --no-images
  for d in /tmp/r/run$rep/*/; do
    mkdir -p "$OUT/run$rep/$(basename $d)"
    [ -f "$d/results.json" ] && gzip -9c "$d/results.json" > "$OUT/run$rep/$(basename $d)/results.json.gz"
  done
done
echo "total $(( $(date +%s)-T0 )) s" >> "$OUT/times.txt"
