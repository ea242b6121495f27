#!/usr/bin/env bash
# Turns a sweep's full-size PNG images into small WebP previews, the only images committed under
# results/ (results/.gitignore keeps the PNGs out of git). Each NAME.png gets NAME.webp beside it:
# lossy WebP at quality 75, scaled down to at most 960 pixels wide (never up), aspect kept. A
# 1920x1080 colour image becomes ~25 KB instead of ~1 MB. The PNGs are left where they are (the
# full-size images stay on the machine that ran the sweep); a preview newer than its PNG is kept.
#
# Usage: bash scripts/previews.sh DIR...
# Then rewrite the folder's page so that it shows the previews (`report` links NAME.webp where
# there is one): hybridbench report DIR/results.json --out DIR/report.html
# Needs cwebp (Debian: apt-get install webp).
set -euo pipefail

readonly kMaxWidth=960
readonly kQuality=75

die() { echo "previews.sh: $*" >&2; exit 2; }

[ $# -ge 1 ] || die "name the folders to convert (usage: bash scripts/previews.sh DIR...)"
command -v cwebp >/dev/null || die "cwebp not found; install it with: apt-get install webp"
for dir in "$@"; do [ -d "$dir" ] || die "$dir is not a folder; name a sweep's output folder"; done

# A PNG's width: the big-endian 32-bit word at byte 16 (the IHDR chunk).
pngWidth() {
  local b
  read -r -a b < <(od -An -tu1 -j16 -N4 "$1")
  [ ${#b[@]} = 4 ] || die "$1: too short to be a PNG"
  echo $(((b[0] << 24) | (b[1] << 16) | (b[2] << 8) | b[3]))
}

made=0
kept=0
while IFS= read -r -d '' png; do
  webp=${png%.png}.webp
  if [ -f "$webp" ] && [ "$webp" -nt "$png" ]; then kept=$((kept + 1)); continue; fi
  [ "$(head -c 8 "$png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] || die "$png is not a PNG"
  resize=()
  if [ "$(pngWidth "$png")" -gt $kMaxWidth ]; then resize=(-resize "$kMaxWidth" 0); fi
  cwebp -quiet -q $kQuality -m 6 -metadata none "${resize[@]}" "$png" -o "$webp.tmp" ||
    die "cwebp failed on $png"
  mv "$webp.tmp" "$webp"
  made=$((made + 1))
done < <(find "$@" -type f -name '*.png' -print0 | LC_ALL=C sort -z)
echo "previews.sh: $made preview(s) written, $kept up to date"
