#!/bin/bash
# Session 39, call 2 (#51): the wide tree by the SAH-optimal collapse (S: the working tree at
# 0b4d149 + SahCollapse as the only collapse) against the greedy collapse (G: call 1's bundle,
# HB_COLLAPSE unset, whose wide trees are 0b4d149's): the issue's three ray sets and the frame's own
# rays through raybench, interleaved, then configs/bvh-width.json's width-4 and width-8 frames swept
# with each for a per-pass compare; warmed by peaks.
set -u
cd "$(dirname "$0")"
tar xf hb39b.tar.xz -C /tmp
B=/tmp/hbx
mkdir -p /tmp/r /tmp/rays /tmp/frame
nvidia-smi > /tmp/r/nvidia-smi.txt
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > /tmp/r/$name.log 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> /tmp/r/times.txt; }
run 60 warm $B/S/hybridbench peaks --json
run 30 export $B/G/hybridbench rays export --scene atrium --size 1920x1080 --out /tmp/rays
run 60 frame-rays $B/G/hybridbench render --size 1920x1080 --set backend=compute --set 'ambient_occlusion={"method": "raytraced", "directions": 8}' --out /tmp/frame/render --rays-out /tmp/frame/rays
for rep in 1 2; do
  for s in camera ao shadow; do
    for b in G S; do run 40 rb-$s-$b-$rep $B/$b/hybridbench raybench /tmp/rays/$s.bin --json /tmp/r/raybench-$s-$b-$rep.json; done
  done
done
for f in /tmp/frame/rays/*.bin; do
  n=$(basename $f .bin)
  for b in G S; do run 60 rb-frame-$n-$b $B/$b/hybridbench raybench $f --json /tmp/r/raybench-frame-$n-$b.json; done
done
for b in G S; do run 150 bvh-$b $B/$b/hybridbench sweep bvh-width-48.json --out /tmp/r/bvh-width-$b --no-images; done
run 60 peaks-S $B/S/hybridbench peaks --json
echo "total $(( $(date +%s)-T0 )) s" >> /tmp/r/times.txt
cp /tmp/r/times.txt "$OUT/"
tar cJf "$OUT/r.tar.xz" -C /tmp r
