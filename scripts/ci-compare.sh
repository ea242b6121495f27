#!/usr/bin/env bash
# A performance check for a CI job on a GPU runner: sweep CONFIG on this machine's GPU, compare the
# result with a stored baseline results.json and fail the job on a regression.
#
#   scripts/ci-compare.sh BASELINE.json [CONFIG] [OUTDIR]
#
# CONFIG defaults to the config the baseline was swept with (its context.config is a full config),
# so a baseline alone is enough. Writes OUTDIR (default out/ci-compare) with the new results.json,
# compare.md (a Markdown table for the job summary; appended to $GITHUB_STEP_SUMMARY when set) and
# compare.junit.xml (JUnit XML: one test case per variant and pass, failed when slower; the builds
# compared and every warning as properties, the warnings again as the suite's system-err) and
# report.html (hybridbench report: the new results' page with the comparison B/A plotted).
# Exit: 0 no regression, 1 a frame or pass time slower than the baseline beyond the threshold
# (hybridbench compare --gate all: a pass gates too, unless its median is under --min-ms on both
# sides), 2 bad input (missing baseline, config or device).
# HYBRIDBENCH (default: hybridbench on PATH, else build/hybridbench), SWEEP_ARGS (e.g. "--frames
# 100 --device 1") and COMPARE_ARGS (e.g. "--threshold 3", or "--gate frame" to gate on frames
# only), NOISE (a noise file for compare --noise, from hybridbench noise) and HISTORY (a folder of
# earlier results: the new ones join it and hybridbench history --gate runs over it) may be set.
# RESULTS=FILE compares that results.json instead of sweeping (e.g. what
# `hybridbench merge` wrote from a fleet's parts, docs/fleet.md); CONFIG is then not used.
set -uo pipefail

if [ $# -lt 1 ] || [ $# -gt 3 ]; then
  echo "usage: scripts/ci-compare.sh BASELINE.json [CONFIG] [OUTDIR]" >&2
  exit 2
fi
baseline="$1"
config="${2:-}"
out="${3:-out/ci-compare}"
hb="${HYBRIDBENCH:-$(command -v hybridbench || echo build/hybridbench)}"
if [ ! -x "$hb" ]; then
  echo "ci-compare: no hybridbench binary at '$hb'; build it (cmake --build build) or set HYBRIDBENCH" >&2
  exit 2
fi
if [ ! -f "$baseline" ]; then
  echo "ci-compare: baseline '$baseline' does not exist; store a results.json from a sweep on this GPU first" >&2
  exit 2
fi
mkdir -p "$out" || exit 2
if [ -n "${RESULTS:-}" ] && [ ! -f "$RESULTS" ]; then
  echo "ci-compare: RESULTS='$RESULTS' does not exist; give the results.json to compare (e.g. hybridbench merge's)" >&2
  exit 2
fi
if [ -z "$config" ] && [ -z "${RESULTS:-}" ]; then
  # The baseline's own config: results.json keeps the full effective config under context.config.
  config="$out/baseline-config.json"
  python3 -c 'import gzip,json,sys; d=open(sys.argv[1],"rb").read(); d=gzip.decompress(d) if d[:2]==b"\x1f\x8b" else d; json.dump(json.loads(d)["context"]["config"], open(sys.argv[2], "w"), indent=2)' \
    "$baseline" "$config" || { echo "ci-compare: '$baseline' holds no context.config; pass CONFIG" >&2; exit 2; }
fi

# NOISE=FILE: a noise file (hybridbench noise): gate only beyond the between-run spread too.
noise=()
if [ -n "${NOISE:-}" ]; then
  if [ ! -f "$NOISE" ]; then
    echo "ci-compare: NOISE='$NOISE' does not exist; write one with 'hybridbench noise A.json B.json ... --out FILE'" >&2
    exit 2
  fi
  noise=(--noise "$NOISE")
fi

# Every pass gates unless COMPARE_ARGS names its own gate.
case " ${COMPARE_ARGS:-} " in
  *" --gate "*) gate=() ;;
  *) gate=(--gate all) ;;
esac

if [ -n "${RESULTS:-}" ]; then
  candidate="$RESULTS"
  echo "ci-compare: comparing $candidate (RESULTS) with $baseline; no sweep"
else
  echo "ci-compare: sweeping $config on this machine's GPU into $out/sweep"
  rm -rf "$out/sweep"
  # shellcheck disable=SC2086  # SWEEP_ARGS is a list of options
  "$hb" sweep "$config" --no-images --out "$out/sweep" ${SWEEP_ARGS:-} || exit 2
  candidate="$out/sweep/results.json"
fi

# shellcheck disable=SC2086  # COMPARE_ARGS is a list of options
"$hb" compare "$baseline" "$candidate" --format junit ${gate[@]+"${gate[@]}"} ${noise[@]+"${noise[@]}"} ${COMPARE_ARGS:-} > "$out/compare.junit.xml"
"$hb" compare "$baseline" "$candidate" --format md ${gate[@]+"${gate[@]}"} ${noise[@]+"${noise[@]}"} ${COMPARE_ARGS:-} > "$out/compare.md"
status=$?
# The page of the new sweep with the comparison (hybridbench report): the job's artifact to open.
# shellcheck disable=SC2086  # COMPARE_ARGS is a list of options
if ! "$hb" report "$candidate" --compare "$baseline" --out "$out/report.html" ${gate[@]+"${gate[@]}"} ${noise[@]+"${noise[@]}"} \
  ${COMPARE_ARGS:-}; then
  echo "ci-compare: report.html not written (see the line above); compare.md stands" >&2
fi
cat "$out/compare.md"
if [ -n "${GITHUB_STEP_SUMMARY:-}" ]; then cat "$out/compare.md" >> "$GITHUB_STEP_SUMMARY"; fi

# HISTORY=DIR: the results history a CI keeps (a cache, an artifact, a branch). The new results join
# it, then hybridbench history looks for changes over all of them: exit 1 too when some series'
# newest segment is slower (a regression that crept in over several runs, which no single compare
# against the baseline sees). Fewer than two comparable runs is a note, not a failure.
if [ -n "${HISTORY:-}" ] && [ $status -le 1 ]; then
  # Written under a temporary name, then renamed: a job cancelled mid-copy leaves no truncated entry.
  entry="$HISTORY/$(date -u +%Y%m%dT%H%M%SZ)-$$"
  mkdir -p "$entry" && cp "$candidate" "$entry/.results.json.part" && mv "$entry/.results.json.part" "$entry/results.json" ||
    { echo "ci-compare: cannot write HISTORY='$HISTORY'" >&2; exit 2; }
  "$hb" history "$HISTORY" --gate --html "$out/history.html" > "$out/history.md" 2> "$out/history.log"
  hstatus=$?
  cat "$out/history.md"
  if [ -n "${GITHUB_STEP_SUMMARY:-}" ]; then cat "$out/history.md" >> "$GITHUB_STEP_SUMMARY"; fi
  case $hstatus in
    0) ;;
    1) echo "ci-compare: REGRESSION in the history $HISTORY: a newest segment is slower (see $out/history.md, $out/history.html)"
       history_gated=1 ;;
    *)
      # Too few runs yet is a note; anything else (a damaged entry, a bad file) is bad input.
      if grep -q -e "one results file has no history" -e "were measured alike" "$out/history.log"; then
        echo "ci-compare: no history yet: $(head -n 1 "$out/history.log")"
      else
        echo "ci-compare: history over HISTORY='$HISTORY' failed: $(head -n 1 "$out/history.log")" >&2
        exit 2
      fi ;;
  esac
fi
case $status in
  0) echo "ci-compare: no regression against $baseline" ;;
  1) echo "ci-compare: REGRESSION against $baseline (see $out/compare.md, $out/report.html)" ;;
  *) echo "ci-compare: compare refused the pair (exit $status)" >&2 ;;
esac
if [ $status -eq 0 ] && [ "${history_gated:-0}" -eq 1 ]; then status=1; fi
exit $status
