#!/bin/bash
# Session 35, call 3: the GPU test suite on the H200, with Debian's validation layer carried (VK_LAYER_PATH). TM = main's hybridbench_tests (1b59ecc) and
# its hybridbench (the CLI tests run it), in 8 shards at once on the one GPU; then P1's AaTest
# (session 35's rejected subgroup items) with its failures in full.
set -u
cd "$(dirname "$0")"
tar xf hb56.tar.xz -C /tmp
tar xf hb60.tar.xz -C /tmp
tar xf hb61.tar.xz -C /tmp
export VK_LAYER_PATH=/tmp/hbx/VL
B=/tmp/hbx
cd ..
ROOT=$PWD
[ -e /work/main ] || { mkdir -p /work && ln -s "$ROOT" /work/main; }
mkdir -p /work/main/build-new && cp $B/TM/hybridbench /work/main/build-new/hybridbench
export LD_LIBRARY_PATH=$B/M/lib
nvidia-smi -L > "$OUT/summary.txt"
echo "root $ROOT; /work/main -> $(readlink -f /work/main)" >> "$OUT/summary.txt"
T0=$(date +%s)
$B/M/hybridbench peaks --json > /tmp/warm.log 2>&1
for i in 0 1 2 3 4 5 6 7; do
  (cd /work/main && GTEST_TOTAL_SHARDS=8 GTEST_SHARD_INDEX=$i HYBRIDBENCH_VALIDATION=1 timeout 420 $B/TM/hybridbench_tests > /tmp/shard$i.log 2>&1; echo "shard $i rc=$?" >> /tmp/rc.txt) &
done
wait
cat /tmp/rc.txt >> "$OUT/summary.txt"
echo "after $(( $(date +%s)-T0 )) s: OK $(cat /tmp/shard*.log | grep -c '^\[       OK \]'), FAILED $(cat /tmp/shard*.log | grep -c '^\[  FAILED  \].*ms)')" >> "$OUT/summary.txt"
grep -h '^\[  FAILED  \].*ms)' /tmp/shard*.log >> "$OUT/summary.txt"
grep -h -B2 -A12 'Failure$' /tmp/shard*.log | head -3000 > "$OUT/failures.txt"
tar czf "$OUT/shards.tar.gz" -C /tmp shard0.log shard1.log shard2.log shard3.log shard4.log shard5.log shard6.log shard7.log
for i in 0 1 2 3 4 5 6 7; do tail -2 /tmp/shard$i.log >> "$OUT/summary.txt"; done
(cd /work/main && HYBRIDBENCH_VALIDATION=1 timeout 120 $B/T/hybridbench_tests_P1 --gtest_filter='AaTest.TimedFrames*' > /tmp/p1.log 2>&1; echo "P1 AaTest rc=$?" >> "$OUT/summary.txt")
head -150 /tmp/p1.log > "$OUT/p1-aatest.txt"
(cd /work/main && HYBRIDBENCH_VALIDATION=1 timeout 120 $B/TM/hybridbench_tests --gtest_filter='AaTest.TimedFrames*' > /tmp/m.log 2>&1; echo "M AaTest rc=$?" >> "$OUT/summary.txt")
echo "total $(( $(date +%s)-T0 )) s" >> "$OUT/summary.txt"
