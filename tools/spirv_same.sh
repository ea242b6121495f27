#!/usr/bin/env bash
# Whether a change left every shader's SPIR-V byte for byte as it was: compiles each shader
# (shaders/**/*.glsl, tests/shaders/*.glsl) at a base revision and in the working tree, the way
# CMakeLists.txt does (glslangValidator --target-env vulkan1.3 -S <stage> --auto-map-bindings
# -I<tree>/shaders; keep the two in step), and compares the two SPIR-V files of each.
#   bash tools/spirv_same.sh [BASE]   BASE a revision, HEAD by default; exits 1 on any difference
set -euo pipefail
cd "$(dirname "$0")/.."
base=${1:-HEAD}
command -v glslangValidator >/dev/null || { echo "spirv_same.sh: glslangValidator not found" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/base_tree"
paths=(shaders)
git cat-file -e "$base:tests/shaders" 2>/dev/null && paths+=(tests/shaders)
git archive "$base" "${paths[@]}" | tar -x -C "$tmp/base_tree"
mkdir -p "$tmp/base_tree/tests/shaders"

compile() {  # TREE OUT: every shader of TREE to OUT/<path with / as __>.spv
  local tree=$1 out=$2 src rel name stage
  mkdir -p "$out"
  while IFS= read -r src; do
    rel=${src#"$tree"/}
    name=$(basename "$src" .glsl)
    stage=${name##*.}
    glslangValidator --target-env vulkan1.3 -S "$stage" --auto-map-bindings -I"$tree/shaders" -o "$out/${rel//\//__}.spv" "$src" \
      >"$tmp/log" 2>&1 || { echo "spirv_same.sh: $rel does not compile ($tree)" >&2; cat "$tmp/log" >&2; exit 2; }
  done < <(find "$tree/shaders" "$tree/tests/shaders" -name '*.glsl' | sort)
}
compile "$tmp/base_tree" "$tmp/base"
compile "$PWD" "$tmp/head"

same=0 differ=0
for f in "$tmp/head"/*.spv "$tmp/base"/*.spv; do
  n=$(basename "$f")
  [[ $f == "$tmp/base"/* && -f "$tmp/head/$n" ]] && continue  # compared from the head side
  if [[ ! -f "$tmp/base/$n" ]]; then echo "new: ${n%.spv}"; differ=$((differ + 1))
  elif [[ ! -f "$tmp/head/$n" ]]; then echo "gone: ${n%.spv}"; differ=$((differ + 1))
  elif cmp -s "$tmp/head/$n" "$tmp/base/$n"; then same=$((same + 1))
  else echo "differs: ${n%.spv}"; differ=$((differ + 1)); fi
done
echo "spirv_same.sh: $same identical, $differ different (against $base)"
[[ $differ -eq 0 ]]
