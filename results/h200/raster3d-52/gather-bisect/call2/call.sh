#!/bin/bash
# Session 33, call 3: #52 the 800x800 indirect frame's gather (+12 % since 6ac3db0; its gather
# compiles to 81 registers). R1 (this session's tree and coarseHolds) against G1 (R1 with one part's
# bounds folded and the tile cull edge by edge) and G2 (R1 without the tile cull); H (1f42f75) as the
# time before 6ac3db0. The 800x800 frame twice, interleaved; the K = 3 stride runs once each.
set -u
cd "$(dirname "$0")"  # run from bundle/: its tar and configs (indirect-cut.json and stride-cut.json are beside this README)
tar xf hb53.tar.xz -C /tmp
B=/tmp/hbx
mkdir -p "$OUT/r" /tmp/r
nvidia-smi > "$OUT/nvidia-smi.txt"
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > "$OUT/r/$name.log" 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> "$OUT/times.txt"; }
keep() { for d in /tmp/r/*/; do [ -f "$d/results.json" ] && gzip -9c "$d/results.json" > "$OUT/r/$(basename $d).results.json.gz"; done; }
run 60 warm $B/R1/hybridbench peaks --json
for rep in 1 2; do
  for b in H R1 G1 G2; do run 45 ind-$b-$rep $B/$b/hybridbench sweep indirect-cut.json --out /tmp/r/ind-$b-$rep --no-images; keep; done
done
for b in R1 G1 G2; do run 70 stride-$b $B/$b/hybridbench sweep stride-cut.json --out /tmp/r/stride-$b --no-images; keep; done
echo "total $(( $(date +%s)-T0 )) s" >> "$OUT/times.txt"
