#!/usr/bin/env bash
# #52: M (HEAD a45b9a8) against O (PASS 0 writes a span a big triangle and the passes after it
# expand the items; the tile pass's fast path), one warmed H200: the 3dr thread-box frames, then the
# bvh-width frames (every pass gating).
set -u
mkdir -p /tmp/hb && tar -xJf bundle/hb10.tar.xz -C /tmp/hb
res=/tmp/k2; mkdir -p $res
nvidia-smi > $res/nvidia-smi.txt 2>&1
M=/tmp/hb/M/hybridbench; O=/tmp/hb/O/hybridbench
$O peaks --json > $res/peaks-warmup.json 2> $res/peaks-warmup.txt
for cfg in r3d-kernels:bundle/r3d-kernels.json bvh-width:configs/bvh-width.json; do
  name=${cfg%%:*}; path=${cfg#*:}
  for v in M O; do
    s=$(date +%s)
    timeout 170 /tmp/hb/$v/hybridbench sweep $path --no-images --out $res/$name-$v > $res/sweep-$name-$v.txt 2>&1
    echo "sweep $name $v rc=$? $(( $(date +%s) - s )) s" >> $res/times.txt
  done
  $O compare $res/$name-M/results.json $res/$name-O/results.json --gate all --format md > $res/compare-$name.md 2>&1
  echo "compare $name rc=$?" >> $res/times.txt
done
cd $res && tar -cJf $OUT/k2.tar.xz --exclude='*.png' .
