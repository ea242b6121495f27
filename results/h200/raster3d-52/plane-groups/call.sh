#!/bin/bash
# Session 38, call 7: N5 = N4 + the tile pass with shared sample planes on 4 threads a pixel (each
# thread a quarter of the planes), the shadow tests with positionsApart. Warmed by peaks; the
# shadow tests; the atrium's aa-cut (3dr-binned aa none and MSAA 16) N4, N5, N4, N5; MSAA 16 on
# microbench-dense N4, N5.
set -u
cd "$(dirname "$0")"
tar xf hb38.tar.xz -C /tmp
B=/tmp/hbx
cd ..
[ -e /work/main ] || { mkdir -p /work && ln -s "$PWD" /work/main; }
mkdir -p /tmp/r
nvidia-smi > /tmp/r/nvidia-smi.txt
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > /tmp/r/$name.log 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> /tmp/r/times.txt; }
run 60 warm $B/N5/hybridbench peaks --json
run 120 shadow-tests env LD_LIBRARY_PATH=$B/N5/lib $B/T/hybridbench_tests --gtest_filter='ShadowScenes/ShadowBackends.*:ShadowComputeTiles.*:ShadowScaledTMin.*'
for i in 1 2; do
  for b in N4 N5; do run 100 aa-$b-$i $B/$b/hybridbench sweep bundle/aa-cut.json --out /tmp/r/aa-$b-$i --no-images; done
done
for b in N4 N5; do run 90 dense-$b $B/$b/hybridbench sweep bundle/dense-msaa.json --out /tmp/r/dense-$b --no-images; done
echo "total $(( $(date +%s)-T0 )) s" >> /tmp/r/times.txt
cp /tmp/r/times.txt "$OUT/"
for d in /tmp/r/*/; do rm -rf "$d"/images "$d"/*.png "$d"/*.exr "$d"/*.html 2>/dev/null; done
tar cJf "$OUT/r.tar.xz" -C /tmp r
