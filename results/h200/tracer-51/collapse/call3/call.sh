#!/bin/bash
# Session 39, call 3 (#51): the final build F (the working tree of d269459: the collapse of least SAH
# cost with the review's fixes) against G (call 1's bundle, HB_COLLAPSE unset: main at 0b4d149's
# greedy collapse): configs/thesis.json swept with each, G then F, for the thesis frames' per-pass
# compare; then the issue's three sets and the frame's own rays through F's raybench; peaks with F
# before (warm-up) and after.
set -u
cd "$(dirname "$0")"
tar xf hb39c.tar.xz -C /tmp
B=/tmp/hbx
mkdir -p /tmp/r /tmp/rays /tmp/frame
nvidia-smi > /tmp/r/nvidia-smi.txt
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > /tmp/r/$name.log 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> /tmp/r/times.txt; }
run 60 warm $B/F/hybridbench peaks --json
run 30 export $B/F/hybridbench rays export --scene atrium --size 1920x1080 --out /tmp/rays
run 60 frame-rays $B/F/hybridbench render --size 1920x1080 --set backend=compute --set 'ambient_occlusion={"method": "raytraced", "directions": 8}' --out /tmp/frame/render --rays-out /tmp/frame/rays
for b in G F; do run 100 thesis-$b $B/$b/hybridbench sweep ../configs/thesis.json --out /tmp/r/thesis-$b --no-images; done
for s in camera ao shadow; do run 40 rb-$s-F $B/F/hybridbench raybench /tmp/rays/$s.bin --json /tmp/r/raybench-$s-F.json; done
for f in /tmp/frame/rays/*.bin; do n=$(basename $f .bin); run 60 rb-frame-$n-F $B/F/hybridbench raybench $f --json /tmp/r/raybench-frame-$n-F.json; done
run 60 peaks-F $B/F/hybridbench peaks --json
echo "total $(( $(date +%s)-T0 )) s" >> /tmp/r/times.txt
cp /tmp/r/times.txt "$OUT/"
tar cJf "$OUT/r.tar.xz" -C /tmp r
