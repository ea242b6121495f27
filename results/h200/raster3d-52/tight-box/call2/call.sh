#!/bin/bash
# Session 41, call 2: prototypes for #52's MSAA 16. A: main at e668b0f. B: r3dScreenBox's box is
# the pixels whose centre lies within 1/16 px of the projected extent (was floor - 1 .. ceil + 1).
# C: shared sample planes key every covered plane with the pixel centre's depth. BC: both.
# Warm with peaks; aa-cut (3dr-binned none and MSAA 16) with A, B, BC; then MSAA 16 alone with
# A, B, BC, C.
set -u
cd "$(dirname "$0")"
tar xf hb41b.tar.xz -C /tmp
B=/tmp/hbx
mkdir -p /tmp/r
nvidia-smi > /tmp/r/nvidia-smi.txt
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > /tmp/r/$name.log 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> /tmp/r/times.txt; }
run 60 warm $B/A/hybridbench peaks --json
for b in A B BC; do run 100 aa-$b $B/$b/hybridbench sweep aa-cut.json --out /tmp/r/aa-$b --no-images; done
for b in A B BC C; do run 100 m16-$b $B/$b/hybridbench sweep aa-msaa16.json --out /tmp/r/m16-$b --no-images; done
echo "total $(( $(date +%s)-T0 )) s" >> /tmp/r/times.txt
cp /tmp/r/times.txt "$OUT/"
for d in /tmp/r/*/; do rm -rf "$d"/images "$d"/*.png "$d"/*.exr "$d"/*.html 2>/dev/null; done
tar cJf "$OUT/r.tar.xz" -C /tmp r
