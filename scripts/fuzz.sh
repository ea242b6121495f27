#!/usr/bin/env bash
# Set-up if needed, then builds the libFuzzer targets into build-fuzz/ (clang, AddressSanitizer
# with leak detection, UndefinedBehaviorSanitizer) and runs each for SECONDS seconds (default 60),
# the targets side by side, one a core. Each starts from its committed seed corpus,
# tests/fuzz/corpus/<target>/, and adds what it discovers to build-fuzz/corpus/<target>/ (kept
# between runs). A crash, a leak, a sanitizer report, an exception other than hb::InputError or an
# input that takes over 10 s fails the run; the input that did it is saved as
# build-fuzz/findings/<target>-crash-<sha1> (or -leak-, -timeout-, -oom-): replay it with
# build-fuzz/fuzz_<target> FILE. Extra libFuzzer flags come from HYBRIDBENCH_FUZZ_FLAGS.
# Usage: scripts/fuzz.sh [SECONDS] [gltf|config]...   (default: all targets)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
[ $# -gt 0 ] && shift
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(gltf config)
case "$seconds" in '' | *[!0-9]*)
  echo "fuzz.sh: SECONDS must be a whole number, got '$seconds'; usage: scripts/fuzz.sh [SECONDS] [gltf|config]..." >&2
  exit 2 ;;
esac
for t in "${targets[@]}"; do
  [ -d "tests/fuzz/corpus/$t" ] || {
    echo "fuzz.sh: no fuzz target '$t' (tests/fuzz/corpus/$t/ is missing); the targets are gltf and config" >&2
    exit 2
  }
done

HYBRIDBENCH_SKIP_BUILD=1 bash scripts/setup.sh
cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang \
  -DCMAKE_CXX_COMPILER=clang++ -DHYBRIDBENCH_FUZZ=ON -DHYBRIDBENCH_WERROR=ON >/dev/null
cmake --build build-fuzz -j"$(nproc)" --target "${targets[@]/#/fuzz_}"

mkdir -p build-fuzz/findings
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1}"
declare -A pid
for t in "${targets[@]}"; do
  mkdir -p "build-fuzz/corpus/$t"
  dict=()
  [ -f "tests/fuzz/$t.dict" ] && dict=("-dict=tests/fuzz/$t.dict")
  # shellcheck disable=SC2086  # HYBRIDBENCH_FUZZ_FLAGS is a list of flags
  "build-fuzz/fuzz_$t" "build-fuzz/corpus/$t" "tests/fuzz/corpus/$t" "${dict[@]}" \
    -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="build-fuzz/findings/$t-" ${HYBRIDBENCH_FUZZ_FLAGS:-} \
    </dev/null >"build-fuzz/fuzz_$t.log" 2>&1 &
  pid[$t]=$!
done
failed=()
for t in "${targets[@]}"; do
  if wait "${pid[$t]}"; then
    runs=$(grep -o 'number_of_executed_units: *[0-9]*' "build-fuzz/fuzz_$t.log" | grep -o '[0-9]*$' || true)
    echo "fuzz_$t: ${seconds} s, no finding${runs:+ ($runs inputs run)}"
  else
    failed+=("$t")
    echo "fuzz_$t: FAILED; the end of build-fuzz/fuzz_$t.log:" >&2
    tail -n 60 "build-fuzz/fuzz_$t.log" >&2
  fi
done
[ ${#failed[@]} -eq 0 ] || {
  echo "fuzz.sh: findings in ${failed[*]}: the inputs are in build-fuzz/findings/" >&2
  exit 1
}
