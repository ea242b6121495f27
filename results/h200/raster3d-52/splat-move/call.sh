#!/bin/bash
# Session 34, call 3: the indirect splat host code moved to indirect_splat.cpp (f5ef1bc; H87 = main at 87a3040) against M (e1df798, before the move): the 800x800 indirect frame with the compute splat (indirect-cut.json), interleaved M, H87, M, H87.
set -u
cd "$(dirname "$0")"
tar xf hb56.tar.xz -C /tmp
tar xf hb58.tar.xz -C /tmp
B=/tmp/hbx
mkdir -p "$OUT/r" /tmp/r /tmp/logs
nvidia-smi > "$OUT/nvidia-smi.txt"
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > "/tmp/logs/$name.log" 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> "$OUT/times.txt"; }
keep() { for d in /tmp/r/*/; do [ -f "$d/results.json" ] && gzip -9c "$d/results.json" > "$OUT/r/$(basename $d).results.json.gz"; done; }
run 60 warm $B/M/hybridbench peaks --json
for rep in 1 2; do
  for b in M H87; do run 90 ind-$b-$rep $B/$b/hybridbench sweep indirect-cut.json --out /tmp/r/ind-$b-$rep --no-images; keep; done
done
echo "total $(( $(date +%s)-T0 )) s" >> "$OUT/times.txt"
