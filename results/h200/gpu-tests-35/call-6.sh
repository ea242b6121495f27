#!/bin/bash
# Session 35, call 6 (main's test with a print, 1b59ecc): which photons escape the closed box on the H200 (main's test + a print of each
# escaped slot: its primary, direction, the GPU's x1 against the CPU's, the CPU's hits from it).
set -u
cd "$(dirname "$0")"
tar xf hb56.tar.xz -C /tmp
tar xf hb64.tar.xz -C /tmp
B=/tmp/hbx
cd ..
[ -e /work/main ] || { mkdir -p /work && ln -s "$PWD" /work/main; }
cd /work/main && LD_LIBRARY_PATH=$B/M/lib timeout 120 $B/TD/hybridbench_tests --gtest_filter='IndirectGpuTest.InAClosed*' > "$OUT/esc.log" 2>&1; echo "rc=$?" >> "$OUT/esc.log"
