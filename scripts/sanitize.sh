#!/usr/bin/env bash
# Set-up if needed, then the unit tests beside the code (src/**/*_test.cpp: no device needed)
# built into build-asan/ with AddressSanitizer (leak detection on) and UndefinedBehaviorSanitizer,
# warnings as errors. Unoptimised (Debug): with the sanitizers it compiles five times faster than
# -O2, and the tests run in one shard a core. Any sanitizer report stops its shard and fails the
# run. Extra arguments go to the test binary, e.g. scripts/sanitize.sh --gtest_filter='Config*'
set -euo pipefail
cd "$(dirname "$0")/.."
HYBRIDBENCH_SKIP_BUILD=1 bash scripts/setup.sh
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DHYBRIDBENCH_SANITIZE=ON -DHYBRIDBENCH_WERROR=ON \
  >/dev/null
cmake --build build-asan -j"$(nproc)" --target hybridbench_cpu_tests
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:check_initialization_order=1:strict_string_checks=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1}"
shards=$(nproc)
pids=()
for ((i = 0; i < shards; ++i)); do
  GTEST_TOTAL_SHARDS=$shards GTEST_SHARD_INDEX=$i build-asan/hybridbench_cpu_tests "$@" \
    >"build-asan/shard-$i.log" 2>&1 &
  pids+=($!)
done
failed=0
for ((i = 0; i < shards; ++i)); do
  if wait "${pids[$i]}"; then
    echo "sanitize.sh: shard $((i + 1))/$shards: $(grep -E '^\[  PASSED  \]' "build-asan/shard-$i.log")"
  else
    failed=1
    echo "sanitize.sh: shard $((i + 1))/$shards FAILED; the end of build-asan/shard-$i.log:" >&2
    tail -n 80 "build-asan/shard-$i.log" >&2
  fi
done
exit $failed
