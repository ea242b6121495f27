#!/bin/bash
# Session 35, call 5: the slab test's reciprocal taken in double (F = 1b59ecc + that) against M
# (e1df798, the same shaders as 1b59ecc otherwise). First the GPU tests that failed on the H200 for
# numbers (photons escaping a closed box, AO, grazing shadows) with F's test binary; then the
# issue's ray sets through raybench and best.json / indirect-cut.json swept, interleaved.
set -u
cd "$(dirname "$0")"
tar xf hb56.tar.xz -C /tmp
tar xf hb60.tar.xz -C /tmp
tar xf hb63.tar.xz -C /tmp
B=/tmp/hbx
mkdir -p "$OUT/r" /tmp/o /tmp/rays
rm -f /tmp/t?.log
nvidia-smi > "$OUT/nvidia-smi.txt"
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > /tmp/o/$name.log 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> "$OUT/times.txt"; }
run 60 warm $B/M/hybridbench peaks --json
ROOT=$(cd .. && pwd)
[ -e /work/main ] || { mkdir -p /work && ln -s "$ROOT" /work/main; }
mkdir -p /work/main/build-new && cp $B/TM/hybridbench /work/main/build-new/hybridbench
F='IndirectGpuTest.*:AoGpuTest.*:ShadowGrazing.*:IndirectBounces*:Raster3dViewsTest.TheHardwarePath*'
for i in 0 1 2 3; do
  (cd /work/main && LD_LIBRARY_PATH=$B/M/lib GTEST_TOTAL_SHARDS=4 GTEST_SHARD_INDEX=$i timeout 200 $B/TF/hybridbench_tests --gtest_filter="$F" > /tmp/t$i.log 2>&1) &
done
wait
echo "tests after $(( $(date +%s)-T0 )) s: OK $(cat /tmp/t?.log | grep -c '^\[       OK \]'), FAILED $(cat /tmp/t?.log | grep -c '^\[  FAILED  \].*ms)')" >> "$OUT/times.txt"
grep -h '^\[  FAILED  \].*ms)' /tmp/t?.log >> "$OUT/times.txt"
cat /tmp/t?.log > /tmp/o/tests-F.log
run 30 export $B/M/hybridbench rays export --scene atrium --size 1920x1080 --out /tmp/rays
for rep in 1 2; do
  for s in camera ao shadow; do
    for b in M F; do run 40 rb-$s-$b-$rep $B/$b/hybridbench raybench /tmp/rays/$s.bin --json /tmp/o/raybench-$s-$b-$rep.json; done
  done
done
for rep in 1 2; do
  for b in M F; do
    run 90 best-$b-$rep $B/$b/hybridbench sweep best.json --out /tmp/o/best-$b-$rep --no-images
    gzip -9c /tmp/o/best-$b-$rep/results.json > /tmp/o/best-$b-$rep.results.json.gz
    run 90 ind-$b-$rep $B/$b/hybridbench sweep indirect-cut.json --out /tmp/o/ind-$b-$rep --no-images
    gzip -9c /tmp/o/ind-$b-$rep/results.json > /tmp/o/ind-$b-$rep.results.json.gz
  done
done
echo "total $(( $(date +%s)-T0 )) s" >> "$OUT/times.txt"
cd /tmp/o && tar czf "$OUT/r/all.tar.gz" *.results.json.gz raybench-*.json tests-F.log *.log
