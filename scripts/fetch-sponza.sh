#!/usr/bin/env bash
# Downloads Crytek Sponza from the Khronos glTF sample models (glTF/Sponza.gltf, Sponza.bin and
# every texture the .gltf names) into scenes/sponza/, where configs/thesis-sponza.json looks for
# it ("../scenes/sponza/Sponza.gltf" relative to configs/). Needs curl or wget and internet access.
#   scripts/fetch-sponza.sh            fetch what is missing (idempotent: files already there stay)
#   scripts/fetch-sponza.sh --force    fetch every file again
# Then, if build/hybridbench exists, checks that the scene loads (hybridbench scene info).
# Exit codes (as hybridbench's): 0 ok, 2 bad usage or no download tool, 3 download or load failed.
# Files are written as NAME.part and renamed when complete, so an interrupted run leaves no
# truncated file behind and the next run fetches only what is missing.
set -euo pipefail
cd "$(dirname "$0")/.."

# The only source: the official KhronosGroup/glTF-Sample-Models repository on GitHub. Its default
# branch is "main" (formerly "master"); SPONZA_REF picks another branch, tag or commit.
REPO_RAW="https://raw.githubusercontent.com/KhronosGroup/glTF-Sample-Models"
REFS=("${SPONZA_REF:-main}")
[ -z "${SPONZA_REF:-}" ] && REFS+=(master)
SUBDIR="2.0/Sponza/glTF"
DEST="scenes/sponza"

force=0
for arg in "$@"; do
  case "$arg" in
    --force) force=1 ;;
    -h|--help) sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "fetch-sponza.sh: unknown argument '$arg'; usage: scripts/fetch-sponza.sh [--force]" >&2; exit 2 ;;
  esac
done

if command -v curl >/dev/null 2>&1; then
  download() { curl -fsSL --retry 2 --connect-timeout 20 -o "$2" "$1"; }
elif command -v wget >/dev/null 2>&1; then
  download() { wget -q --tries=3 --timeout=20 -O "$2" "$1"; }
else
  echo "fetch-sponza.sh: neither curl nor wget is installed; install one (apt-get install curl) and rerun" >&2
  exit 2
fi

no_network_help() {
  echo "fetch-sponza.sh: could not download $1${last_error:+ ($last_error)}" >&2
  echo "  This machine may have no internet access (or GitHub is unreachable). On a machine that has it," >&2
  echo "  run this script there, or download the folder $SUBDIR of" >&2
  echo "  https://github.com/KhronosGroup/glTF-Sample-Models and copy its files into $DEST/;" >&2
  echo "  then rerun this script to check them. Files already in $DEST/ were kept." >&2
  rmdir "$DEST" 2>/dev/null || true  # leave no empty folder behind
}

# fetch NAME: downloads $SUBDIR/NAME to $DEST/NAME unless it is there already (or --force).
# Tries each ref in turn; returns non-zero when none of them served the file.
ref_used=""
last_error=""
fetch() {
  local name="$1" target="$DEST/$1"
  if [ $force = 0 ] && [ -s "$target" ]; then return 0; fi
  mkdir -p "$(dirname "$target")"
  local ref refs=("${REFS[@]}")
  [ -n "$ref_used" ] && refs=("$ref_used")  # the ref that served Sponza.gltf serves the rest
  for ref in "${refs[@]}"; do
    if last_error=$(download "$REPO_RAW/$ref/$SUBDIR/$name" "$target.part" 2>&1); then
      mv -f "$target.part" "$target"
      last_error=""
      ref_used="$ref"
      return 0
    fi
  done
  rm -f "$target.part"
  last_error="${last_error##*$'\n'}"  # the last attempt's message (curl --retry prints one each)
  return 1
}

if ! fetch Sponza.gltf; then
  no_network_help "$REPO_RAW/${REFS[0]}/$SUBDIR/Sponza.gltf"
  exit 3
fi

# Every external file the .gltf names (buffers[].uri, images[].uri), data: URIs excepted. The
# file is minified JSON from glTF-Transform; a grep for "uri":"..." is enough and needs no jq.
mapfile -t uris < <(grep -o '"uri"[[:space:]]*:[[:space:]]*"[^"]*"' "$DEST/Sponza.gltf" |
                    sed 's/^.*"\([^"]*\)"$/\1/' | grep -v '^data:' | sort -u)
if [ ${#uris[@]} -eq 0 ]; then
  echo "fetch-sponza.sh: $DEST/Sponza.gltf names no buffer or image files; it is not the Khronos Sponza (delete it and rerun)" >&2
  exit 3
fi

failed=0
fetched=0
for uri in "${uris[@]}"; do
  # Refuse names that could escape $DEST (absolute paths, ..) or need URL decoding.
  if [[ "$uri" == /* || "$uri" == *..* || ! "$uri" =~ ^[A-Za-z0-9._/-]+$ ]]; then
    echo "fetch-sponza.sh: skipping unexpected uri '$uri' in $DEST/Sponza.gltf" >&2
    failed=$((failed + 1))
    continue
  fi
  was_there=0
  [ $force = 0 ] && [ -s "$DEST/$uri" ] && was_there=1
  if fetch "$uri"; then
    [ $was_there = 0 ] && fetched=$((fetched + 1))
  else
    echo "fetch-sponza.sh: could not download $SUBDIR/$uri${last_error:+ ($last_error)}" >&2
    failed=$((failed + 1))
  fi
done

if [ $failed -gt 0 ]; then
  echo "fetch-sponza.sh: $failed of ${#uris[@]} files are missing from $DEST/ (see above); rerun to fetch only those (the others were kept)" >&2
  exit 3
fi
echo "fetch-sponza.sh: $DEST/ holds Sponza.gltf and its ${#uris[@]} files ($fetched downloaded now${ref_used:+, from $ref_used})"

if [ -x build/hybridbench ]; then
  if ! build/hybridbench scene info "$DEST/Sponza.gltf"; then
    echo "fetch-sponza.sh: build/hybridbench cannot load $DEST/Sponza.gltf (see above); rerun with --force to fetch it again" >&2
    exit 3
  fi
else
  echo "fetch-sponza.sh: build/hybridbench not built yet; check the scene later with: build/hybridbench scene info $DEST/Sponza.gltf"
fi
echo "fetch-sponza.sh: run the thesis sweep on it with: scripts/run.sh sweep configs/thesis-sponza.json"
