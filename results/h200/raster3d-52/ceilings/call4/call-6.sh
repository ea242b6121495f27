#!/bin/bash
# Session 38, call 6: the shadow tests as committed (pixels with the same rays held to the bound,
# each frame's rays to the CPU's), on the H200 without validation (no layer there).
set -u
cd "$(dirname "$0")"
tar xf hb38.tar.xz -C /tmp
B=/tmp/hbx
cd ..
[ -e /work/main ] || { mkdir -p /work && ln -s "$PWD" /work/main; }
LD_LIBRARY_PATH=$B/N4/lib timeout 300 $B/T/hybridbench_tests --gtest_filter='ShadowScenes/ShadowBackends.*:ShadowComputeTiles.*:ShadowScaledTMin.*:ShadowHardCases.*' > "$OUT/shadow-tests.log" 2>&1
echo "rc=$?" >> "$OUT/shadow-tests.log"
