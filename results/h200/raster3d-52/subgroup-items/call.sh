#!/bin/bash
# Session 35, call 1: #52 the shared sample planes' tile pass with each pixel's planes spread over
# its subgroup (P1: every subgroup takes both subgroup barriers for every triangle; P2: a subgroup
# with no pixel that needs the triangle skips it) against M (e1df798, today's shaders), on
# aa-cut.json (3dr-binned without AA and with MSAA 16 at 1080p); interleaved, twice. Then the AA
# GPU tests on the H200 (the timed frames' planes against the CPU rasterization).
set -u
cd "$(dirname "$0")"
tar xf hb56.tar.xz -C /tmp
tar xf hb59.tar.xz  # P1, P2, and T: P1's hybridbench_tests -C /tmp
B=/tmp/hbx
mkdir -p "$OUT/r" /tmp/r
nvidia-smi > "$OUT/nvidia-smi.txt"
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > /tmp/r/$name.log 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> "$OUT/times.txt"; tail -3 /tmp/r/$name.log >> "$OUT/times.txt"; }
keep() { for d in /tmp/r/*/; do [ -f "$d/results.json" ] && gzip -9c "$d/results.json" > "$OUT/r/$(basename $d).results.json.gz"; done; }
run 60 warm $B/M/hybridbench peaks --json
for rep in 1 2; do
  for b in M P1 P2; do run 90 aa-$b-$rep $B/$b/hybridbench sweep aa-cut.json --out /tmp/r/aa-$b-$rep --no-images; keep; done
done
cd ..
LD_LIBRARY_PATH=$B/M/lib timeout 200 $B/T/hybridbench_tests --gtest_filter='AaTest.*' > /tmp/r/gtest.log 2>&1; echo "gtest rc=$?" >> "$OUT/times.txt"; grep -E "OK|FAILED|PASSED|Which is|plane" /tmp/r/gtest.log | head -30 >> "$OUT/times.txt"
echo "total $(( $(date +%s)-T0 )) s" >> "$OUT/times.txt"
