#!/bin/bash
# Session 38, call 4 (N4 = the working tree at 07461c7 + session 37's changes; shaders as N2's):
# warmed by peaks; the shadow tests whose reference is now exactBackend() (the driver's pipeline on
# a GPU without ray query); configs/ceilings.json on microbench-tiny.
set -u
cd "$(dirname "$0")"
tar xf hb38.tar.xz -C /tmp
B=/tmp/hbx
cd ..
[ -e /work/main ] || { mkdir -p /work && ln -s "$PWD" /work/main; }
mkdir -p /tmp/r
nvidia-smi > /tmp/r/nvidia-smi.txt
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > /tmp/r/$name.log 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> /tmp/r/times.txt; }
run 30 devices $B/N4/hybridbench devices
run 60 warm $B/N4/hybridbench peaks --json
run 120 shadow-tests env LD_LIBRARY_PATH=$B/N4/lib $B/T/hybridbench_tests --gtest_filter='ShadowScenes/ShadowBackends.*:ShadowComputeTiles.*:ShadowScaledTMin.*' --gtest_output=xml:/tmp/r/shadow-tests.xml
run 330 ceil-tiny $B/N4/hybridbench sweep configs/ceilings.json --scene microbench-tiny --out /tmp/r/ceil-tiny --no-images
echo "total $(( $(date +%s)-T0 )) s" >> /tmp/r/times.txt
cp /tmp/r/times.txt "$OUT/"
for d in /tmp/r/*/; do rm -rf "$d"/images "$d"/*.png "$d"/*.exr 2>/dev/null; done
tar cJf "$OUT/r.tar.xz" -C /tmp r
