#!/usr/bin/env bash
# Set-up if needed, check the formatting, build (Release, warnings as errors), run every test on the Vulkan device that
# is present (lavapipe on a machine without a GPU) with validation layers on. Arguments go to ctest;
# without any (the full run CI makes) the unit tests also run under AddressSanitizer and UBSan
# (scripts/sanitize.sh) and each fuzzer runs for 60 s (scripts/fuzz.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
HYBRIDBENCH_SKIP_BUILD=1 bash scripts/setup.sh
bash scripts/format.sh --check  # the tree follows .clang-format
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DHYBRIDBENCH_WERROR=ON >/dev/null
cmake --build build -j"$(nproc)"
export HYBRIDBENCH_VALIDATION=1
# lavapipe's thread count: both cores, but no more (CI has 2).
export LP_NUM_THREADS="${LP_NUM_THREADS:-$(nproc)}"
# Two tests at a time: a lavapipe test spends much of its time compiling pipelines on one thread, so
# on CI's 2 cores the suite took 450 s with -j2 against 700-820 s with -j1 (at bbbade5); -j3 was slower
# than -j2 at 25deb97 (docs/contributing.md, "Where CI's time goes").
(cd build && ctest --output-on-failure -j2 --timeout 900 "$@")
if [ $# -eq 0 ]; then
  bash scripts/sanitize.sh
  bash scripts/fuzz.sh 60
fi
