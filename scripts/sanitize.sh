#!/usr/bin/env bash
# Set-up if needed, then the unit tests beside the code (src/**/*_test.cpp: no device needed)
# under two sanitizer builds, warnings as errors:
#  1. build-asan/: AddressSanitizer (leak detection on) and UndefinedBehaviorSanitizer, every test.
#     Unoptimised (Debug): with the sanitizers it compiles five times faster than -O2, and the
#     tests run in one shard a core.
#  2. build-tsan/: ThreadSanitizer (it cannot share a build with ASan), Debug at -O1, target
#     hybridbench_tsan_tests (the four test files of TSAN_TESTS in CMakeLists.txt), the tests
#     that run code on several threads ($tsan_tests below: parallelFor and the analyses that use
#     it, each compared bit for bit with its serial run in analysis_threads_test.cpp), in one
#     process with HYBRIDBENCH_THREADS=4 whatever the cores. On 2 cores its cold build takes 7.3
#     min of CPU (about 4 min of wall time on idle cores) and its run 7 s (docs/contributing.md).
# Any sanitizer report stops its run and fails the script (ThreadSanitizer: halt_on_error=1,
# exit code 66); no suppressions. HYBRIDBENCH_SANITIZERS picks the builds ("address thread" by
# default; "thread" for TSan alone). Extra arguments go to the test binaries after the script's
# own filter, so a --gtest_filter replaces it, e.g. scripts/sanitize.sh --gtest_filter='Config*'
set -euo pipefail
cd "$(dirname "$0")/.."
sanitizers="${HYBRIDBENCH_SANITIZERS:-address thread}"
for s in $sanitizers; do
  [[ $s == address || $s == thread ]] ||
    { echo "sanitize.sh: HYBRIDBENCH_SANITIZERS=\"$sanitizers\": each word must be address or thread" >&2; exit 2; }
done
HYBRIDBENCH_SKIP_BUILD=1 bash scripts/setup.sh

# The unit tests of the multithreaded code: parallel.h itself, the analysis on threads against
# the serial one (analysis_threads_test.cpp), and the tests of each analysis that calls
# parallelFor (culling reference, ray accounting, reference surface, oracle, shadow comparison).
tsan_tests='ParallelFor.*:AnalysisThreads.*:CullingAnalysis.*:RayAccounting.*:ReferenceSurface.*:Oracle.*'
tsan_tests+=':NormalAccuracy.*:CompareShadows.*'

build() {  # build dir, HYBRIDBENCH_SANITIZE value, target
  cmake -S . -B "$1" -DCMAKE_BUILD_TYPE=Debug -DHYBRIDBENCH_SANITIZE="$2" -DHYBRIDBENCH_WERROR=ON >/dev/null
  cmake --build "$1" -j"$(nproc)" --target "$3"
}

failed=0
if [[ " $sanitizers " == *" address "* ]]; then
  build build-asan address hybridbench_cpu_tests
  export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:check_initialization_order=1:strict_string_checks=1}"
  export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1}"
  shards=$(nproc)
  pids=()
  for ((i = 0; i < shards; ++i)); do
    GTEST_TOTAL_SHARDS=$shards GTEST_SHARD_INDEX=$i build-asan/hybridbench_cpu_tests "$@" \
      >"build-asan/shard-$i.log" 2>&1 &
    pids+=($!)
  done
  for ((i = 0; i < shards; ++i)); do
    if wait "${pids[$i]}"; then
      echo "sanitize.sh: shard $((i + 1))/$shards: $(grep -E '^\[  PASSED  \]' "build-asan/shard-$i.log")"
    else
      failed=1
      echo "sanitize.sh: shard $((i + 1))/$shards FAILED; the end of build-asan/shard-$i.log:" >&2
      tail -n 80 "build-asan/shard-$i.log" >&2
    fi
  done
fi

if [[ " $sanitizers " == *" thread "* ]]; then
  start=$SECONDS
  build build-tsan thread hybridbench_tsan_tests
  built=$SECONDS
  # Each suite of the filter must have tests in the binary: a suite whose file is missing from
  # TSAN_TESTS (CMakeLists.txt) would otherwise be skipped without a word.
  listed=$(build-tsan/hybridbench_tsan_tests --gtest_list_tests --gtest_filter="$tsan_tests")
  for suite in ${tsan_tests//:/ }; do
    if ! grep -qx "${suite%.\*}\." <<<"$listed"; then
      echo "sanitize.sh: the ThreadSanitizer filter names $suite but hybridbench_tsan_tests has no such test;" \
        "add its file to TSAN_TESTS in CMakeLists.txt" >&2
      failed=1
    fi
  done
  log=build-tsan/tsan.log
  if TSAN_OPTIONS="${TSAN_OPTIONS:-halt_on_error=1:exitcode=66:second_deadlock_stack=1}" \
    HYBRIDBENCH_THREADS="${HYBRIDBENCH_THREADS:-4}" \
    build-tsan/hybridbench_tsan_tests --gtest_filter="$tsan_tests" "$@" >"$log" 2>&1; then
    echo "sanitize.sh: ThreadSanitizer: $(grep -E '^\[  PASSED  \]' "$log") (build $((built - start)) s, run $((SECONDS - built)) s)"
  else
    failed=1
    if grep -q 'WARNING: ThreadSanitizer' "$log"; then
      echo "sanitize.sh: ThreadSanitizer FAILED; its report in $log:" >&2
      sed -n '/WARNING: ThreadSanitizer/,$p' "$log" | head -n 120 >&2
    else
      echo "sanitize.sh: ThreadSanitizer run FAILED; the end of $log:" >&2
      tail -n 80 "$log" >&2
      if grep -q 'unexpected memory mapping' "$log"; then
        echo "sanitize.sh: this kernel's address randomisation is too wide for GCC 12's TSan;" \
          "sudo sysctl vm.mmap_rnd_bits=28 fixes it" >&2
      fi
    fi
  fi
fi
exit $failed
