#!/bin/bash
# Session 39, call 1: the 4-wide tree collapsed greedily (G, today) against the SAH-optimal collapse
# (Ylitie et al. 2017) at three triangle-to-node cost ratios (HB_COLLAPSE=sah:1:R), one bundle, the
# issue's three ray sets and the frame's own rays through raybench, interleaved; warmed by peaks.
set -u
cd "$(dirname "$0")"
tar xf hb39.tar.xz -C /tmp
B=/tmp/hbx/N
mkdir -p /tmp/r /tmp/rays /tmp/frame
nvidia-smi > /tmp/r/nvidia-smi.txt
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > /tmp/r/$name.log 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> /tmp/r/times.txt; }
declare -A MODE=([G]=greedy [S15]=sah:1:0.15 [S3]=sah:1:0.3 [S5]=sah:1:0.5 [S10]=sah:1:1)
run 60 warm $B/hybridbench peaks --json
run 30 export $B/hybridbench rays export --scene atrium --size 1920x1080 --out /tmp/rays
run 60 frame-rays $B/hybridbench render --size 1920x1080 --set backend=compute --set 'ambient_occlusion={"method": "raytraced", "directions": 8}' --out /tmp/frame/render --rays-out /tmp/frame/rays
ls -la /tmp/frame/rays >> /tmp/r/times.txt
for rep in 1 2; do
  for s in camera ao shadow; do
    for v in G S15 S3 S5 S10; do run 40 rb-$s-$v-$rep env HB_COLLAPSE=${MODE[$v]} $B/hybridbench raybench /tmp/rays/$s.bin --json /tmp/r/raybench-$s-$v-$rep.json; done
  done
done
for f in /tmp/frame/rays/*.bin; do
  n=$(basename $f .bin)
  for v in G S3 S10; do run 60 rb-frame-$n-$v env HB_COLLAPSE=${MODE[$v]} $B/hybridbench raybench $f --json /tmp/r/raybench-frame-$n-$v.json; done
done
echo "total $(( $(date +%s)-T0 )) s" >> /tmp/r/times.txt
cp /tmp/r/times.txt "$OUT/"
tar cJf "$OUT/r.tar.xz" -C /tmp r
