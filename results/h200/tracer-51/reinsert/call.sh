#!/bin/bash
# Session 33, call 1: #51 the trace tree optimized by reinsertion (R1 = 9f69304 + the splat's
# coarseHolds + kTraceBvhBuild reinsertRounds 40) against C1 (9f69304 + coarseHolds, the tree as
# built): the issue's three ray sets and the frame's own rays through raybench, interleaved, then
# configs/bvh-width.json swept with each build for a per-pass compare.
set -u
cd "$(dirname "$0")"
tar xf hb50.tar.xz -C /tmp
B=/tmp/hbx
mkdir -p "$OUT/r" /tmp/rays /tmp/frame
nvidia-smi > "$OUT/nvidia-smi.txt"
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > "$OUT/r/$name.log" 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> "$OUT/times.txt"; }
run 60 warm $B/C1/hybridbench peaks --json
run 30 export $B/C1/hybridbench rays export --scene atrium --size 1920x1080 --out /tmp/rays
run 60 frame-rays $B/C1/hybridbench render --size 1920x1080 --set backend=compute --set 'ambient_occlusion={"method": "raytraced", "directions": 8}' --out /tmp/frame/render --rays-out /tmp/frame/rays
for rep in 1 2; do
  for s in camera ao shadow; do
    for b in C1 R1; do run 40 rb-$s-$b-$rep $B/$b/hybridbench raybench /tmp/rays/$s.bin --json "$OUT/r/raybench-$s-$b-$rep.json"; done
  done
done
for f in /tmp/frame/rays/*.bin; do
  n=$(basename $f .bin)
  for b in C1 R1; do run 60 rb-frame-$n-$b $B/$b/hybridbench raybench $f --json "$OUT/r/raybench-frame-$n-$b.json"; done
done
for b in C1 R1; do run 170 bvh-$b $B/$b/hybridbench sweep ../configs/bvh-width.json --out "$OUT/r/bvh-width-$b" --no-images; done
echo "total $(( $(date +%s)-T0 )) s" >> "$OUT/times.txt"
