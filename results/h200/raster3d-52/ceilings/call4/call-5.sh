#!/bin/bash
# Session 38, call 5: call 4's four failed shadow tests again, their messages now saying why the
# masks differ (position, normal, lights traced, or the same rays).
set -u
cd "$(dirname "$0")"
tar xf hb38.tar.xz -C /tmp
B=/tmp/hbx
cd ..
[ -e /work/main ] || { mkdir -p /work && ln -s "$PWD" /work/main; }
LD_LIBRARY_PATH=$B/N4/lib timeout 200 $B/T/hybridbench_tests --gtest_filter='ShadowComputeTiles.*:ShadowScenes/ShadowBackends.*/atrium:ShadowScenes/ShadowBackends.*/thin_gap:ShadowScenes/ShadowBackends.*/far_origin' > "$OUT/shadow-why.log" 2>&1
echo "rc=$?" >> "$OUT/shadow-why.log"
