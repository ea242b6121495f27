#!/bin/bash
# Session 36, call 4: every test but the CLI suites on the H200 (no VK_KHR_ray_query there), without
# validation (no layer installed there), 8 shards: the test binary at 6c99679 plus the change that
# gives the shadow tests exactBackend() (the driver's ray-tracing pipeline there) or skips those
# that compare ray query itself, and open-occluder's ground points taken within 0.25 m of y = 0.
set -u
cd "$(dirname "$0")"
tar xf hb36b.tar.xz -C /tmp
tar xf hb36t.tar.xz -C /tmp
B=/tmp/hbx
cd ..
[ -e /work/main ] || { mkdir -p /work && ln -s "$PWD" /work/main; }
mkdir -p /work/main/build-new && cp $B/M/bin/hybridbench /work/main/build-new/hybridbench
export LD_LIBRARY_PATH=$B/M/lib
T0=$(date +%s)
F='-AntiAliasingSweep.*:AutoScene.*:CiCompareDefaults.*:Cli.*:CompareContext.*:CompareGate.*:ContinuumSweep.*:Determinism.*:EffectsCli.*:GltfCompressed.*:HelpCli.*:HistoryCli.*:LoaderCli.*:NewUser.*:Peaks.*:ReportCli.*:SceneIdentity.*:Scenes.*:Sweep.*:SweepDevices.*:SweepResume.*:SweepShard.*:SweepWatchdog.*'
for i in 0 1 2 3 4 5 6 7; do
  (cd /work/main && GTEST_TOTAL_SHARDS=8 GTEST_SHARD_INDEX=$i timeout 420 $B/T/hybridbench_tests --gtest_filter="$F" > /tmp/q$i.log 2>&1; echo "shard $i rc=$?" >> /tmp/q-rc.log) &
done
wait
{ cat /tmp/q-rc.log; echo "after $(( $(date +%s)-T0 )) s: OK $(cat /tmp/q?.log | grep -c '^\[       OK \]'), SKIPPED $(cat /tmp/q?.log | grep -c '^\[  SKIPPED \].*ms)'), FAILED $(cat /tmp/q?.log | grep -c '^\[  FAILED  \].*ms)')"; grep -h '^\[  FAILED  \].*ms)\|^\[  SKIPPED \].*ms)' /tmp/q?.log; } > "$OUT/summary.txt"
nvidia-smi > "$OUT/nvidia-smi.txt"
tar czf "$OUT/q.tar.gz" -C /tmp q0.log q1.log q2.log q3.log q4.log q5.log q6.log q7.log
