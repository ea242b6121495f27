#!/usr/bin/env bash
# Installs hybridbench's build and test dependencies from Debian packages, then builds Release
# into build/. Idempotent; run as root or with sudo. Mesa's lavapipe comes from
# bookworm-backports (25.x: the one in bookworm main has no ray tracing). The backports entry is
# derived from the machine's own Debian sources entry (same mirror), so no mirror address is
# written into the repository.
set -euo pipefail
cd "$(dirname "$0")/.."

SUDO=""
if [ "$(id -u)" != 0 ]; then
  if command -v sudo >/dev/null; then SUDO="sudo"; else
    echo "setup.sh: needs root to install packages; run it as root or install sudo" >&2; exit 2
  fi
fi

PACKAGES=(cmake g++ make pkg-config glslang-tools libvulkan-dev libglm-dev libtinygltf-dev
  nlohmann-json3-dev libcli11-dev libstb-dev libgtest-dev vulkan-validationlayers vulkan-tools
  libssl-dev libglvnd0 libglx0 libegl1 libgl1 libopengl0
  clang libclang-rt-14-dev llvm  # the fuzzers: clang, libFuzzer's runtime, llvm-symbolizer
  clang-format                   # scripts/format.sh --check (CI)
  libdraco-dev libmeshoptimizer-dev  # compressed glTF: KHR_draco_mesh_compression, EXT_meshopt_compression
  libwebp-dev libavif-dev        # glTF textures: EXT_texture_webp, EXT_texture_avif
  libcmark-gfm-dev libcmark-gfm-extensions-dev  # report.html: the tables' Markdown to HTML
  libspirv-cross-c-shared-dev    # descriptor bindings read back from the shaders' SPIR-V
  zlib1g-dev                     # committed results files kept gzipped (results.json.gz)
  python3-yaml shellcheck        # docs/fleet/'s scheduler examples (tests/fleet_examples_test.py)
  slurm-wlm munge                # the Slurm example run for real (tests/fleet_slurm_test.sh starts its own daemons)
  chromium)                      # the HTML report's browser test (headless, driven by playwright-core)
# node and npm run the glTF validator test; a node that brings its own npm (NodeSource's) is kept,
# since Debian's npm package conflicts with it.
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then PACKAGES+=(nodejs npm); fi
BACKPORTS_LIST=/etc/apt/sources.list.d/hybridbench-backports.list

missing=()
for p in "${PACKAGES[@]}"; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
mesa_ok=0
if dpkg -s mesa-vulkan-drivers >/dev/null 2>&1; then
  case "$(dpkg-query -W -f='${Version}' mesa-vulkan-drivers)" in 2[5-9].*|[3-9]*) mesa_ok=1 ;; esac
fi

if [ ${#missing[@]} -gt 0 ] || [ $mesa_ok = 0 ]; then
  # Derive "bookworm-backports" from the first Debian entry the machine already has.
  if ! grep -rqs "bookworm-backports" /etc/apt/sources.list /etc/apt/sources.list.d/; then
    mirror=""
    if [ -f /etc/apt/sources.list.d/debian.sources ]; then
      mirror=$(awk '/^URIs:/ && $2 !~ /security/ {print $2; exit}' /etc/apt/sources.list.d/debian.sources)
    fi
    if [ -z "$mirror" ] && [ -f /etc/apt/sources.list ]; then
      mirror=$(awk '$1=="deb" && $0 !~ /security/ && $0 ~ /bookworm/ {for(i=2;i<=NF;i++) if ($i ~ /^(https?|file|ftp):/) {print $i; exit}}' /etc/apt/sources.list)
    fi
    if [ -z "$mirror" ]; then
      echo "setup.sh: found no Debian bookworm entry in /etc/apt/sources.list{,.d} to derive bookworm-backports from; add one (deb MIRROR bookworm main) and rerun" >&2
      exit 2
    fi
    echo "deb $mirror bookworm-backports main" | $SUDO tee "$BACKPORTS_LIST" >/dev/null
  fi
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${PACKAGES[@]}"
  $SUDO apt-get install -y -qq --no-install-recommends -t bookworm-backports mesa-vulkan-drivers
fi

# The npm tools the tests run (the Khronos glTF Validator, playwright-core, gltfpack,
# @gltf-transform/cli): the versions pinned in tools/package.json (integrity in
# tools/package-lock.json) into tools/node_modules/ (git-ignored); nothing to do when they are there.
# Without the npm registry the run goes on and the tests that use them fail, saying how to install them.
if ! node scripts/validate-gltf.mjs --check-installed >/dev/null 2>&1 ||
  ! [ -x tools/node_modules/.bin/gltfpack ] || ! [ -x tools/node_modules/.bin/gltf-transform ] ||
  ! [ -d tools/node_modules/playwright-core ]; then
  npm ci --prefix tools --no-audit --no-fund >/dev/null ||
    echo "setup.sh: could not install the npm test tools (is the npm registry reachable?); the tests that use them fail until 'npm ci --prefix tools' succeeds" >&2
fi

if [ "${HYBRIDBENCH_SKIP_BUILD:-0}" != 1 ]; then
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build build -j"$(nproc)"
fi
