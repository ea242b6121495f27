#!/usr/bin/env bash
# #52: M (a45b9a8) against P (2aa102a: spans, count over runs, brute force a run a workgroup, the
# tile pass's fast path), one warmed H200: the 3dr thread-box frames, the bvh-width frames (every
# pass gating in k2), and the CAD meshes at 720p
# three times each (overflows, same work).
set -u
mkdir -p /tmp/hb && tar -xJf bundle/hb11.tar.xz -C /tmp/hb
res=/tmp/k3; mkdir -p $res
nvidia-smi > $res/nvidia-smi.txt 2>&1
M=/tmp/hb/M/hybridbench; P=/tmp/hb/P/hybridbench
$P peaks --json > $res/peaks-warmup.json 2> $res/peaks-warmup.txt
for cfg in r3d-kernels:bundle/r3d-kernels.json; do
  name=${cfg%%:*}; path=${cfg#*:}
  for v in M P; do
    s=$(date +%s)
    timeout 160 /tmp/hb/$v/hybridbench sweep $path --no-images --out $res/$name-$v > $res/sweep-$name-$v.txt 2>&1
    echo "sweep $name $v rc=$? $(( $(date +%s) - s )) s" >> $res/times.txt
  done
  $P compare $res/$name-M/results.json $res/$name-P/results.json --gate all --format md > $res/compare-$name.md 2>&1
  echo "compare $name rc=$?" >> $res/times.txt
done
for m in gears helix bearing; do
  for method in 3dr 3dr-binned; do
    for k in 1 2 3; do
      timeout 60 $P render --scene scenes/external/mcad-$m.glb --size 1280x720 --set primary=$method --set world_pos=hit --set shading=visbuffer --out /tmp/cad/$m-$method-$k > /dev/null 2>&1
      python3 -c "
import json; p=json.load(open('/tmp/cad/$m-$method-$k/render.json'))['primary']
print('$m $method P $k', p['tile_list_overflows'], p.get('list_capacity'), p.get('list_grown_from'), p['list_entries'], p['pixels_tested'], p['coverage_check']['holes'], p['coverage_check']['double_covers'])" >> $res/cad.txt 2>&1
    done
  done
done
echo "cad done $(date -u +%T)" >> $res/times.txt
cd $res && tar -cJf $OUT/k3.tar.xz --exclude='*.png' .
