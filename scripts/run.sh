#!/usr/bin/env bash
# Set-up if needed, build, run the main job (the embedded default sweep on device 0). Extra
# arguments go to hybridbench, e.g. scripts/run.sh sweep configs/ci.json --out out/ci
set -euo pipefail
cd "$(dirname "$0")/.."
HYBRIDBENCH_SKIP_BUILD=1 bash scripts/setup.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)"
exec build/hybridbench "$@"
