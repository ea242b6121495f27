#!/usr/bin/env bash
# Rewrites the meshes made outside this repository (scenes/external/README.md): each NAME.scad
# here, rendered by OpenSCAD (its CGAL kernel makes the triangles) from the MCAD parts library,
# exported as OFF and transcoded to NAME.glb by off-to-glb.mjs (positions and indices as written).
# Needs the Debian packages openscad and openscad-mcad (not in scripts/setup.sh: CI reads the
# committed .glb files and never runs this) and node.
# Usage: scenes/external/regenerate.sh [--check]
#   --check: render into a temporary folder and compare with the committed files byte for byte
#            (exit 1 naming the first that differs).
set -euo pipefail
cd "$(dirname "$0")"
for tool in openscad node; do
  command -v "$tool" >/dev/null || {
    echo "regenerate.sh: $tool is not installed; apt-get install openscad openscad-mcad nodejs" >&2
    exit 2
  }
done
[ -d /usr/share/openscad/libraries/MCAD ] || {
  echo "regenerate.sh: the MCAD library is missing; apt-get install openscad-mcad" >&2
  exit 2
}
check=0
[ "${1:-}" = "--check" ] && check=1
out=.
if [ $check = 1 ]; then
  out="$(mktemp -d)"
  trap 'rm -rf "$out"' EXIT
fi
for scad in *.scad; do
  name="${scad%.scad}"
  echo "regenerate.sh: $scad (OpenSCAD's CGAL render takes up to a few minutes)"
  openscad -o "$out/$name.off" "$scad" 2>"$out/$name.openscad.log" || {
    cat "$out/$name.openscad.log" >&2
    exit 1
  }
  node off-to-glb.mjs "$out/$name.off" "$out/$name.glb"
  rm -f "$out/$name.off" "$out/$name.openscad.log"
  if [ $check = 1 ] && ! cmp -s "$out/$name.glb" "$name.glb"; then
    echo "regenerate.sh: $name.glb differs from what $scad renders today" >&2
    exit 1
  fi
done
