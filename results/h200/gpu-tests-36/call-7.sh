#!/bin/bash
# Session 36, call 7 (call 6: the same, sampling the wrong process): does a process that opens and closes VulkanContext again and again run out of
# something on the NVIDIA driver? One light GPU test repeated 150 times; its open files, threads and
# resident memory sampled every second.
set -u
cd "$(dirname "$0")"
tar xf hb36b.tar.xz -C /tmp
tar xf hb36t.tar.xz -C /tmp
B=/tmp/hbx
cd ..
[ -e /work/main ] || { mkdir -p /work && ln -s "$PWD" /work/main; }
export LD_LIBRARY_PATH=$B/M/lib
ulimit -n > "$OUT/fd.txt"
(cd /work/main && timeout 200 $B/T/hybridbench_tests --gtest_filter='AoGpuTest.HbaoAndGtaoBuildNoMapsAndNoRayTracer' --gtest_repeat=150 > /tmp/r6.log 2>&1; echo "rc=$?" >> /tmp/r6.log) &
sleep 2
P=$(pgrep -x hybridbench_tes | head -1)
while kill -0 $P 2>/dev/null; do echo "$(date +%s) fds $(ls /proc/$P/fd 2>/dev/null | wc -l) $(grep -E 'Threads|VmRSS' /proc/$P/status 2>/dev/null | tr -s ' \t' ' ' | tr '\n' ' ') ok $(grep -c '^\[       OK' /tmp/r6.log) nodriver $(grep -c 'no Vulkan driver' /tmp/r6.log)" >> "$OUT/fd.txt"; ls -l /proc/$P/fd 2>/dev/null | awk '{print $NF}' | sed 's/[0-9]*$//' | sort | uniq -c | sort -rn | head -5 >> "$OUT/fd.txt"; sleep 1; done
wait
gzip -c /tmp/r6.log > "$OUT/r6.log.gz"
