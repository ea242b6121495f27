#!/usr/bin/env bash
# Device run for issue #18 (session 6). Writes everything under $OUT.
set -u
# t NAME CMD...: runs CMD, appends "NAME <wall ms> rc=<exit>" to timing.txt
t() { local name=$1; shift; local s; s=$(date +%s%N); "$@"; local rc=$?
  echo "$name $(( ($(date +%s%N) - s) / 1000000 )) ms rc=$rc" >> "$OUT/timing.txt"; return $rc; }
B=bundle/hybridbench
O="$OUT"
mkdir -p "$O/byo"
$B --version > "$O/version.txt" 2>&1
$B devices > "$O/devices.txt" 2>&1
nvidia-smi > "$O/nvidia-smi.txt" 2>&1
# 1. Bring your own glTF: the atrium without camera and lights.
$B scene export atrium /tmp/atrium-bare.glb --no-camera --no-lights > "$O/byo/export.log" 2>&1
for v in "auto:" "auto-1000:--set light_count=1000 --set light_lists=zbin"; do
  name=${v%%:*}; args=${v#*:}
  t "$name" timeout -s KILL 60 $B render --scene /tmp/atrium-bare.glb --size 1920x1080 $args \
    --out "$O/byo/render-$name" > "$O/byo/render-$name.log" 2>&1
done
t cornell timeout -s KILL 60 $B render --scene scenes/cornell-box.gltf --size 1920x1080 \
  --out "$O/byo/render-cornell" > "$O/byo/render-cornell.log" 2>&1
t byo-sweep timeout -s KILL 120 $B sweep out/dev/byo.json --out "$O/byo/sweep" --no-images \
  > "$O/byo/sweep.log" 2>&1
# 2. Concurrent sweeps: the thesis config once alone, then twice at once on the one GPU (A/A).
t thesis-single timeout -s KILL 120 $B sweep --device 0 --out "$O/thesis-single" --no-images \
  > "$O/thesis-single.log" 2>&1
t thesis-aa timeout -s KILL 180 $B sweep --device 0,0 --out "$O/thesis-aa" --no-images \
  > "$O/thesis-aa.log" 2>&1
$B compare "$O"/thesis-aa/0-*/results.json "$O"/thesis-aa/1-*/results.json > "$O/thesis-aa-compare.md" 2>&1
echo "exit $?" >> "$O/thesis-aa-compare.md"
$B compare results/h200/many-lights/thesis/results.json.gz "$O/thesis-single/results.json" > "$O/thesis-vs-stored.md" 2>&1
echo "exit $?" >> "$O/thesis-vs-stored.md"
# 3. The CI recipe on a real GPU: sweep, compare with the stored H200 baseline.
t ci-compare env HYBRIDBENCH=bundle/hybridbench timeout -s KILL 120 bash scripts/ci-compare.sh \
  results/h200/many-lights/thesis/results.json.gz configs/thesis.json "$O/ci" > "$O/ci-compare.log" 2>&1
echo "exit $?" >> "$O/ci-compare.log"
# Bring back one archive without images and one with the images worth looking at.
cd "$O"
tar czf /tmp/results.tgz --exclude='*.png' . 
tar czf /tmp/images.tgz $(ls byo/render-*/color.png byo/render-*/rays.png byo/render-cornell/ao.png byo/render-cornell/indirect.png byo/render-auto/lights_per_tile.png 2>/dev/null)
find "$O" -mindepth 1 -delete
mv /tmp/results.tgz /tmp/images.tgz "$O"/
ls -la "$O"
