#!/usr/bin/env bash
# #52: M (a45b9a8) against Q (1fd7422: spans, the count pass's 64-way search, brute force a run a
# workgroup, the tile pass's fast path), one warmed H200: the 3dr thread-box frames; then Q alone on
# the bvh-width frames.
set -u
mkdir -p /tmp/hb && tar -xJf bundle/hb12.tar.xz -C /tmp/hb
res=/tmp/k4; mkdir -p $res
nvidia-smi > $res/nvidia-smi.txt 2>&1
M=/tmp/hb/M/hybridbench; Q=/tmp/hb/Q/hybridbench
$Q peaks --json > $res/peaks-warmup.json 2> $res/peaks-warmup.txt
for v in M Q; do
  s=$(date +%s)
  timeout 150 /tmp/hb/$v/hybridbench sweep bundle/r3d-kernels.json --no-images --out $res/r3d-kernels-$v > $res/sweep-r3d-kernels-$v.txt 2>&1
  echo "sweep r3d-kernels $v rc=$? $(( $(date +%s) - s )) s" >> $res/times.txt
done
$Q compare $res/r3d-kernels-M/results.json $res/r3d-kernels-Q/results.json --gate all --format md > $res/compare-r3d-kernels.md 2>&1
echo "compare rc=$?" >> $res/times.txt
s=$(date +%s)
timeout 170 $Q sweep configs/bvh-width.json --no-images --out $res/bvh-width-Q > $res/sweep-bvh-width-Q.txt 2>&1
echo "sweep bvh-width Q rc=$? $(( $(date +%s) - s )) s" >> $res/times.txt
cd $res && tar -cJf $OUT/k4.tar.xz --exclude='*.png' .
