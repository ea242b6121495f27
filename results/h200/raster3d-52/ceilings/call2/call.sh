#!/bin/bash
# Session 37, call 2: N2 = N (call 1) + the keep-alive instance never destroyed (N's every command
# exited with SIGSEGV after writing its results), tile/resolve/triangle rates without a device
# peak, and configs/ceilings.json with a 3840x2160 variant. Exit codes of N and N2 first; warmed by
# peaks; the ceilings on microbench-dense and microbench-262144, the atrium's aa-cut twice, the
# K = 3 cut once.
set -u
cd "$(dirname "$0")"
tar xf hb37.tar.xz -C /tmp
B=/tmp/hbx
mkdir -p /tmp/r
nvidia-smi > /tmp/r/nvidia-smi.txt
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > /tmp/r/$name.log 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> /tmp/r/times.txt; }
run 30 devices-N $B/N/hybridbench devices
run 30 devices-N2 $B/N2/hybridbench devices
run 60 warm $B/N2/hybridbench peaks --json
run 200 ceil-dense $B/N2/hybridbench sweep ../configs/ceilings.json --out /tmp/r/ceil-dense --no-images
run 240 ceil-262144 $B/N2/hybridbench sweep ../configs/ceilings.json --scene microbench-262144 --out /tmp/r/ceil-262144 --no-images
run 120 aa-N2-1 $B/N2/hybridbench sweep aa-cut.json --out /tmp/r/aa-N2-1 --no-images
run 150 stride-cut $B/N2/hybridbench sweep stride-cut.json --out /tmp/r/stride-cut --no-images
echo "total $(( $(date +%s)-T0 )) s" >> /tmp/r/times.txt
cp /tmp/r/times.txt "$OUT/"
for d in /tmp/r/*/; do rm -rf "$d"/images "$d"/*.png "$d"/*.exr 2>/dev/null; done
tar cJf "$OUT/r.tar.xz" -C /tmp r
