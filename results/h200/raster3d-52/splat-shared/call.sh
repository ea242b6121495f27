#!/bin/bash
# Session 32, call 4: #52 the splat's steps each declaring only their shared memory (S1 = 1cea398)
# against main (B0 = 57fcee5) on the two K = 3 stride runs (bundle/stride-cut.json). Call 3 ran the
# full stride config, four times over, and its results did not come back (the call's time ran out).
set -u
cd "$(dirname "$0")"
tar xf hb48.tar.xz -C /tmp
B=/tmp/hbx
mkdir -p "$OUT/r" /tmp/r
nvidia-smi > "$OUT/nvidia-smi.txt"
T0=$(date +%s)
run() { local name=$1; shift; local s=$(date +%s); timeout 80 "$@" > "/tmp/r/$name.log" 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> "$OUT/times.txt"; }
keep() { for d in /tmp/r/*/; do [ -f "$d/results.json" ] && gzip -9c "$d/results.json" > "$OUT/r/$(basename $d).results.json.gz"; done; }
run warm $B/B0/hybridbench peaks --json
run stride-B0 $B/B0/hybridbench sweep stride-cut.json --out /tmp/r/stride-B0 --no-images; keep
run stride-S1 $B/S1/hybridbench sweep stride-cut.json --out /tmp/r/stride-S1 --no-images; keep
