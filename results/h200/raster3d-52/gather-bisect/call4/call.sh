#!/bin/bash
# Session 33, call 5: #52 the timed gather compiled without the count code (S2, photon_splat.comp.glsl
# and photon_splat_count.comp.glsl from photon_splat_gather.glsl.inc) against R1 (main's code before
# it) and H (1f42f75, before 6ac3db0): the 800x800 frame, then the K = 3 stride runs.
set -u
cd "$(dirname "$0")"  # run from bundle/: its tar and configs (indirect-cut.json and stride-cut.json are beside this README)
tar xf hb55.tar.xz -C /tmp
B=/tmp/hbx
mkdir -p "$OUT/r" /tmp/r
nvidia-smi > "$OUT/nvidia-smi.txt"
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > "$OUT/r/$name.log" 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> "$OUT/times.txt"; }
keep() { for d in /tmp/r/*/; do [ -f "$d/results.json" ] && gzip -9c "$d/results.json" > "$OUT/r/$(basename $d).results.json.gz"; done; }
run 60 warm $B/S2/hybridbench peaks --json
for b in H R1 S2; do run 45 ind-$b $B/$b/hybridbench sweep indirect-cut.json --out /tmp/r/ind-$b --no-images; keep; done
for b in R1 S2; do run 70 stride-$b $B/$b/hybridbench sweep stride-cut.json --out /tmp/r/stride-$b --no-images; keep; done
echo "total $(( $(date +%s)-T0 )) s" >> "$OUT/times.txt"
