#!/bin/bash
# Brute force's item pass with the small boxes' fast path (H, 190bf36) against main before the
# fast path (A, 73d9924). Warm with peaks; brute-cut.json (3dr, 2dr and 3dr-binned at the 64-pixel
# thread box, atrium 1080p) A H.
set -u
cd "$(dirname "$0")"
tar xf hb42d.tar.xz -C /tmp
B=/tmp/hbx
mkdir -p /tmp/r
nvidia-smi > /tmp/r/nvidia-smi.txt
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > /tmp/r/$name.log 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> /tmp/r/times.txt; }
run 40 warm $B/H/hybridbench peaks --json
for b in A H; do run 70 brute-$b $B/$b/hybridbench sweep brute-cut.json --out /tmp/r/brute-$b --no-images; done
echo "total $(( $(date +%s)-T0 )) s" >> /tmp/r/times.txt
cp /tmp/r/times.txt "$OUT/"
for d in /tmp/r/*/; do rm -rf "$d"/images "$d"/*.png "$d"/*.exr "$d"/*.html 2>/dev/null; done
tar cJf "$OUT/r.tar.xz" -C /tmp r
