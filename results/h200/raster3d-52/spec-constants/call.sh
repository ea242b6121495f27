#!/bin/bash
# Session 34, call 2: #52 whether the 3DR shaders' specialization constants of value 0 in timed
# frames cost the H200's driver, as the splat gather's count code did (session 33): V = main's
# code (f5ef1bc) with raster3d_common.glsl.inc's ANALYSIS, METHOD2D and PROJECTION plain constants
# (0, 0, perspective; its analysis frames count nothing), against M (e1df798, the same shaders as
# f5ef1bc). aa-cut.json: 3dr-binned without AA and with MSAA 16 at 1080p; interleaved, twice.
set -u
cd "$(dirname "$0")"
tar xf hb56.tar.xz -C /tmp
tar xf hb57.tar.xz -C /tmp
B=/tmp/hbx
mkdir -p "$OUT/r" /tmp/r
nvidia-smi > "$OUT/nvidia-smi.txt"
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > "$OUT/r/$name.log" 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> "$OUT/times.txt"; }
keep() { for d in /tmp/r/*/; do [ -f "$d/results.json" ] && gzip -9c "$d/results.json" > "$OUT/r/$(basename $d).results.json.gz"; done; }
run 60 warm $B/M/hybridbench peaks --json
for rep in 1 2; do
  for b in M V; do run 90 aa-$b-$rep $B/$b/hybridbench sweep aa-cut.json --out /tmp/r/aa-$b-$rep --no-images; keep; done
done
echo "total $(( $(date +%s)-T0 )) s" >> "$OUT/times.txt"
