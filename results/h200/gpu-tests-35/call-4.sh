#!/bin/bash
# Session 35, call 4: the exactness tests on the H200 without validation (none installed there):
# main's hybridbench_tests (1b59ecc) with the AA test printing its first differing keys.
set -u
cd "$(dirname "$0")"
tar xf hb56.tar.xz -C /tmp
tar xf hb60.tar.xz -C /tmp
tar xf hb62.tar.xz -C /tmp
B=/tmp/hbx
cd ..
[ -e /work/main ] || { mkdir -p /work && ln -s "$PWD" /work/main; }
mkdir -p /work/main/build-new && cp $B/TM/hybridbench /work/main/build-new/hybridbench
export LD_LIBRARY_PATH=$B/M/lib
rm -f /tmp/q*.log
T0=$(date +%s)
F='AaTest.*:Raster3d*:ShadowGrazing.*:Determinism.*:Ldm*:Indirect*:Ao*:ShadowHardCases.*:ShadowNormals.*:ShadowPositions.*:Environment*:LightCulling*'
for i in 0 1 2 3 4 5 6 7; do
  (cd /work/main && GTEST_TOTAL_SHARDS=8 GTEST_SHARD_INDEX=$i timeout 300 $B/TM/hybridbench_tests_dbg --gtest_filter="$F" > /tmp/q$i.log 2>&1; echo "shard $i rc=$?" >> /tmp/q-rc.log) &
done
wait
{ cat /tmp/q-rc.log; echo "after $(( $(date +%s)-T0 )) s: OK $(cat /tmp/q?.log | grep -c '^\[       OK \]'), FAILED $(cat /tmp/q?.log | grep -c '^\[  FAILED  \].*ms)')"; grep -h '^\[  FAILED  \].*ms)' /tmp/q?.log; } > "$OUT/summary.txt"
tar czf "$OUT/q.tar.gz" -C /tmp q0.log q1.log q2.log q3.log q4.log q5.log q6.log q7.log
