#!/bin/bash
# Session 33, call 4: #52 the 800x800 indirect frame's gather (+12 % since 6ac3db0). R1 (main's code)
# against VMIN (R1's gather without 6ac3db0's stride, parts and count code: H's main() and the tile cull)
# and VNOCOUNT (R1's gather without the count code); H (1f42f75) as the time before 6ac3db0. The
# 800x800 frame twice, interleaved; the K = 3 stride runs once each (VMIN's stride-4 light is wrong: timing only).
set -u
cd "$(dirname "$0")"  # run from bundle/: its tar and configs (indirect-cut.json and stride-cut.json are beside this README)
tar xf hb54.tar.xz -C /tmp
B=/tmp/hbx
mkdir -p "$OUT/r" /tmp/r
nvidia-smi > "$OUT/nvidia-smi.txt"
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > "$OUT/r/$name.log" 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> "$OUT/times.txt"; }
keep() { for d in /tmp/r/*/; do [ -f "$d/results.json" ] && gzip -9c "$d/results.json" > "$OUT/r/$(basename $d).results.json.gz"; done; }
run 60 warm $B/R1/hybridbench peaks --json
for rep in 1 2; do
  for b in H R1 VMIN VNOCOUNT; do run 45 ind-$b-$rep $B/$b/hybridbench sweep indirect-cut.json --out /tmp/r/ind-$b-$rep --no-images; keep; done
done
for b in R1 VMIN; do run 70 stride-$b $B/$b/hybridbench sweep stride-cut.json --out /tmp/r/stride-$b --no-images; keep; done
echo "total $(( $(date +%s)-T0 )) s" >> "$OUT/times.txt"
