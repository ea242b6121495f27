#!/usr/bin/env bash
# #52: Q (1fd7422) against R (the tile pass's shared layout written by storeSetup), one warmed H200,
# the best frame's 3dr-binned primary at box 64.
set -u
mkdir -p /tmp/hb && tar -xJf bundle/hb13.tar.xz -C /tmp/hb
res=/tmp/k5; mkdir -p $res
nvidia-smi > $res/nvidia-smi.txt 2>&1
/tmp/hb/R/hybridbench peaks --json > $res/peaks-warmup.json 2> $res/peaks-warmup.txt
for v in Q R; do timeout 60 /tmp/hb/$v/hybridbench sweep bundle/r3d-box64.json --no-images --out $res/box64-$v > $res/sweep-$v.txt 2>&1; echo "$v rc=$?" >> $res/times.txt; done
/tmp/hb/R/hybridbench compare $res/box64-Q/results.json $res/box64-R/results.json --gate all --format md > $res/compare.md 2>&1
cd $res && tar -cJf $OUT/k5.tar.xz --exclude='*.png' .
