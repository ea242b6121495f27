#!/bin/bash
# Session 32, call 1: #51 the fma slab test (A1 = 9b06797) against main (B0 = 57fcee5): the issue's
# three ray sets and the frame's own rays through raybench, interleaved, then configs/bvh-width.json
# swept with each build for a per-pass compare.
set -u
cd "$(dirname "$0")"
tar xf hb46.tar.xz -C /tmp
B=/tmp/hbx
mkdir -p "$OUT/r" /tmp/rays /tmp/frame
nvidia-smi > "$OUT/nvidia-smi.txt"
T0=$(date +%s)
run() { local name=$1; shift; local s=$(date +%s); timeout 250 "$@" > "$OUT/r/$name.log" 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> "$OUT/times.txt"; }
run warm $B/B0/hybridbench peaks --json
run export $B/A1/hybridbench rays export --scene atrium --size 1920x1080 --out /tmp/rays
run frame-rays $B/B0/hybridbench render --size 1920x1080 --set backend=compute --set 'ambient_occlusion={"method": "raytraced", "directions": 8}' --out /tmp/frame/render --rays-out /tmp/frame/rays
ls -la /tmp/rays /tmp/frame/rays >> "$OUT/times.txt"
for rep in 1 2; do
  for s in camera ao shadow; do
    for b in B0 A1; do run rb-$s-$b-$rep $B/$b/hybridbench raybench /tmp/rays/$s.bin --json "$OUT/r/raybench-$s-$b-$rep.json"; done
  done
done
for f in /tmp/frame/rays/*.bin; do
  n=$(basename $f .bin)
  for b in B0 A1; do run rb-frame-$n-$b $B/$b/hybridbench raybench $f --json "$OUT/r/raybench-frame-$n-$b.json"; done
done
for b in B0 A1; do run bvh-$b $B/$b/hybridbench sweep ../configs/bvh-width.json --out "$OUT/r/bvh-width-$b" --no-images; done
cd "$OUT" && tar czf res.tar.gz r times.txt && rm -rf r
