#!/bin/bash
# Session 41, call 1: prototypes. A: main at e668b0f. C: the tile pass with shared sample planes
# keys every covered plane with the pixel centre's depth (one depth a pixel and triangle, not one a
# plane). T1: the closest-hit traversal keeps the watertight test's ray constants and the direction
# in shared memory; T2: the same constants packed in registers (k as one uint).
# Warm with peaks; the issue's three sets with A, T1, T2 interleaved; aa-cut with A, msaa16 with C.
set -u
cd "$(dirname "$0")"
tar xf hb41.tar.xz -C /tmp
B=/tmp/hbx
mkdir -p /tmp/r /tmp/rays
nvidia-smi > /tmp/r/nvidia-smi.txt
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > /tmp/r/$name.log 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> /tmp/r/times.txt; }
run 60 warm $B/A/hybridbench peaks --json
run 30 export $B/A/hybridbench rays export --scene atrium --size 1920x1080 --out /tmp/rays
for s in camera ao shadow; do
  for b in A T1 T2; do run 40 rb-$s-$b $B/$b/hybridbench raybench /tmp/rays/$s.bin --json /tmp/r/raybench-$s-$b.json; done
done
run 100 aa-A $B/A/hybridbench sweep aa-cut.json --out /tmp/r/aa-A --no-images
run 100 aa-C $B/C/hybridbench sweep aa-msaa16.json --out /tmp/r/aa-C --no-images
run 100 aa-A2 $B/A/hybridbench sweep aa-msaa16.json --out /tmp/r/aa-A2 --no-images
echo "total $(( $(date +%s)-T0 )) s" >> /tmp/r/times.txt
cp /tmp/r/times.txt "$OUT/"
for d in /tmp/r/*/; do rm -rf "$d"/images "$d"/*.png "$d"/*.exr "$d"/*.html 2>/dev/null; done
tar cJf "$OUT/r.tar.xz" -C /tmp r
