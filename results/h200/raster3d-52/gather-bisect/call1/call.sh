#!/bin/bash
# Session 33, call 2: #52 the 800x800 indirect frame's photon_splat.gather (+12 % between fa55b82
# and 57fcee5) bisected: H (1f42f75, fa55b82's splat), 6ac3db0 (later stride, the quad cull),
# fb69eaf (the rows of bins) and M0 (main, 9f69304), twice, interleaved; the single-bin steps'
# coarseHolds (C1) against M0 on the K = 3 stride runs; #53 the thesis on the driver's ray-tracing
# pipeline twice on one H200 (an A/A pair).
set -u
cd "$(dirname "$0")"  # run from bundle/: its tar and configs (indirect-cut.json and stride-cut.json are beside this README)
[ -d /tmp/hbx/M0 ] || tar xf hb50.tar.xz -C /tmp
B=/tmp/hbx
mkdir -p "$OUT/r" /tmp/r
nvidia-smi > "$OUT/nvidia-smi.txt"
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > "$OUT/r/$name.log" 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> "$OUT/times.txt"; }
keep() { for d in /tmp/r/*/; do [ -f "$d/results.json" ] && gzip -9c "$d/results.json" > "$OUT/r/$(basename $d).results.json.gz"; done; }
run 60 warm $B/M0/hybridbench peaks --json
for rep in 1 2; do
  for b in H R6ac3db0 Rfb69eaf M0; do run 45 ind-$b-$rep $B/$b/hybridbench sweep indirect-cut.json --out /tmp/r/ind-$b-$rep --no-images; keep; done
done
for b in M0 C1; do run 70 stride-$b $B/$b/hybridbench sweep stride-cut.json --out /tmp/r/stride-$b --no-images; keep; done
for rep in 1 2; do run 110 thesis-pipeline-$rep $B/M0/hybridbench sweep ../configs/thesis.json --set backend=pipeline --out /tmp/r/thesis-pipeline-$rep --no-images; keep; done
echo "total $(( $(date +%s)-T0 )) s" >> "$OUT/times.txt"
