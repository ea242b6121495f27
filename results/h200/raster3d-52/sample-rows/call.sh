#!/bin/bash
# Session 36, call 1: X (main 0391103 + the sample planes' coverage from the centre's rows at the
# sample, per-plane early-z (#52), and the closest-hit stack's code and distance in one 8-byte local
# entry (#51)) against M (main at 0391103): aa-cut.json (3dr-binned, none and MSAA 16, 1080p) and
# the issue's three ray sets through raybench, interleaved M, X, twice; warmed by peaks first.
set -u
cd "$(dirname "$0")"
tar xf hb36.tar.xz -C /tmp
B=/tmp/hbx
mkdir -p /tmp/r /tmp/rays
nvidia-smi > /tmp/r/nvidia-smi.txt
T0=$(date +%s)
run() { local t=$1 name=$2; shift 2; local s=$(date +%s); timeout $t "$@" > /tmp/r/$name.log 2>&1; local rc=$?; echo "$name rc=$rc $(( $(date +%s)-s )) s (at $(( $(date +%s)-T0 )) s)" >> /tmp/r/times.txt; }
run 60 warm $B/M/hybridbench peaks --json
run 30 export $B/M/hybridbench rays export --scene atrium --size 1920x1080 --out /tmp/rays
for rep in 1 2; do
  for b in M X; do run 90 aa-$b-$rep $B/$b/hybridbench sweep aa-cut.json --out /tmp/r/aa-$b-$rep --no-images; done
  for s in camera ao shadow; do
    for b in M X; do run 40 rb-$s-$b-$rep $B/$b/hybridbench raybench /tmp/rays/$s.bin --json /tmp/r/raybench-$s-$b-$rep.json; done
  done
done
echo "total $(( $(date +%s)-T0 )) s" >> /tmp/r/times.txt
cp /tmp/r/times.txt "$OUT/"
for d in /tmp/r/aa-*/; do rm -rf "$d"/images "$d"/*.png 2>/dev/null; done
tar cJf "$OUT/r.tar.xz" -C /tmp r
