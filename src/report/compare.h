// Comparison of two results files (two GPUs, two builds): per variant and per pass, the ratio of
// medians B/A with a confidence interval, a two-sided Mann-Whitney U test and a verdict; a
// regression flag for CI (exit code 1 when a row the gate counts is "slower": the frames by
// default, the passes too with --gate all).
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "base/numbers.h"

namespace hb {

struct NoiseModel;

// Which "slower" rows make a regression (exit 1): the frames only, the passes only, or both.
enum class CompareGate { Frame, Passes, All };
const char* toString(CompareGate gate);

struct CompareOptions {
  double thresholdPct = 5;  // a ratio within 1 ± threshold/100 is "same" even when significant
  double alpha = 0.05;      // significance level of the test; the CI is at 1 - alpha
  bool force = false;       // compare even when the scenes or configs differ (warns instead)
  CompareGate gate = CompareGate::Frame;
  // A pass whose median is under this on both sides is reported but never gates. 0 by default: each
  // row's own floor (CompareRow::floorMs) replaced the fixed 0.02 ms.
  double minMs = 0;
  // The between-run noise (noise_model.h), or null: within-run noise only.
  const NoiseModel* noise = nullptr;
};

// Below kMinSamplesForVerdict samples on a side, or with a CV above kMaxQuietCv, a result that is
// not significant reads "too noisy" rather than "same". 0.10: with n = 30 the median's standard
// error is about 1.25 * 0.10 / sqrt(30) = 2.3 %, so a 5 % change would be barely two standard
// errors away; noisier runs cannot support a claim of "same" at the default threshold.
constexpr size_t kMinSamplesForVerdict = 5;
constexpr double kMaxQuietCv = 0.10;
// Fewer samples than this on a side gives a warning: the test has little power (google/benchmark
// warns likewise for its U test).
constexpr size_t kFewSamplesWarning = 20;

struct CompareRow {
  std::string variant;    // run name, matched between A and B
  std::string pass;       // "frame" or a pass name ("shadows", ...)
  size_t nA = 0, nB = 0;  // samples per side
  double medianA = 0, medianB = 0;
  double cvA = 0, cvB = 0;
  // B/A (> 1: B is slower): the Hodges-Lehmann estimate of the ratio (exp of the median of
  // the pairwise log b_j - log a_i), the estimator of the interval beside it and of the U test;
  // medianB / medianA where a side has no samples.
  double ratio = 0;
  double ciLow = 0, ciHigh = 0;  // ratioInterval(A, B, alpha), around `ratio`: NaN without samples
  double p = 1;                  // Mann-Whitney two-sided; NaN without samples
  // "faster" | "slower" | "same" | "too noisy", or "not timed": a pass (not the frame) measured
  // on a CPU device on either side, whose per-pass times mean nothing (results' timing_caveat).
  std::string verdict;
  bool gates = false;  // "slower" and counted by the gate: a regression
  std::string tracer;  // B's run's ray tracer (backend_choice.ran, else the device's rt_backend)
  // The absolute floor: a slower row gates only when medianB - medianA exceeds it. Twice the
  // timestamps' resolution (the smallest step between two samples of the pass on either side, at
  // least the device's timestampPeriod: each median is a difference of two quantized timestamps),
  // plus z times the model's launch jitter where a noise model covers the device.
  double floorMs = 0;
  // The between-run band (noise_model.h): a slower row gates only when B/A exceeds 1 + bandPct/100;
  // NaN where no noise model covers the row.
  double bandPct = kNaN;
  // Why a "slower" row does not gate, "" otherwise: "within the between-run band", "under the floor".
  std::string held;
};

// What made one side's results (its context): the device and the build. A field the file does
// not record is empty.
struct CompareSide {
  std::string device = "unknown";  // context.device.name
  std::string deviceType;          // context.device.type: discrete, integrated, virtual, cpu, other
  std::string driver;              // context.device.driver
  std::string revision;            // context.tool.git: the build's git revision
  std::string version;             // context.tool.version
  std::string date;                // context.host.date: when the sweep started (UTC, ISO 8601)
  // The ray tracer that traced (runs[].backend_choice.ran; per run where runs differ):
  // results_identity.h tracedBy.
  std::string tracer;
};

struct CompareReport {
  std::string deviceA, deviceB;  // context.device.name, "unknown" when absent
  CompareSide a, b;
  // Both sides name their device type and the two differ (a discrete GPU against a CPU, ...): B/A
  // then measures the devices, not a change of build; the first warning says so.
  bool devicesDifferInKind = false;
  double thresholdPct = 5, alpha = 0.05;
  std::vector<CompareRow> rows;  // per matched variant: "frame" first, then passes in frame order
  double geomeanRatio = 0;       // geometric mean of the frame-level ratios (NaN when none)
  // Each once: a warning that holds for several variants is one line that counts them.
  std::vector<std::string> warnings;
  // What a side's times cannot be used for ("A: <caveat>"), from its context (timingCaveats).
  std::vector<std::string> caveats;
  CompareGate gate = CompareGate::Frame;
  double minMs = 0;
  // Which noise the verdicts used: "within-run" (each run's frames), or the noise file's
  // "between-run (FILE: N A/A pairs)".
  std::string noise = "within-run";
  bool regression = false;  // any row gates
  // One line per row that gates: "<variant>: <pass> B/A 1.087 [1.080, 1.094]".
  std::vector<std::string> failures;
};

// Compares results file b against a (docs/results-format.md, schema_version 1).
// Throws InputError when either is not a schema-1 results file, or (unless options.force) when
// the scene's content (context.scene.sha256, and environment_sha256), the config's scene (a
// built-in's name; a glTF's path aside), the resolution or the config's variants differ; the
// message names the first field that differs (base/json_diff.h) and both values there. The same
// inputs at other paths (another checkout, another runner), runs whose status is not "ok", a
// variant traced by different ray tracers, variants or passes present on one side only, and small
// samples give warnings, not errors.
CompareReport compareResults(const nlohmann::json& a, const nlohmann::json& b, const CompareOptions& options);

// A Markdown table for the console and for CI logs, then the geometric mean, the regression
// flag and the warnings.
std::string formatCompare(const CompareReport& report);

// JUnit XML, as CI systems read test reports: one testsuite, one testcase per (variant, pass)
// (classname "hybridbench.<variant>", name the pass, time B's median in seconds), a <failure> where
// the verdict is "slower" (passes included; the exit code still follows the frame rows only), a
// <skipped> where it is "too noisy"; the devices and builds (a_*, b_*), threshold, alpha, geometric mean
// and each warning as properties, and the warnings again as the suite's <system-err>.
std::string formatCompareJunit(const CompareReport& report);

nlohmann::json toJson(const CompareReport& report);

// The smallest step between two distinct samples (ms), at least `period`: the resolution the
// timestamps gave a pass (the NVIDIA driver's 1 ns period steps by 32 ns on the H200); `period`
// when no two samples differ.
double sampleResolution(std::vector<double> samples, double period);

// One row from two sample sets (the detection trials of noise_model.h): as compareResults makes
// each row, with the device model, ray tracer and timestamp periods (ms) it would read from B.
// The noise classes of runs swept at the same time as other sweeps (`sweep --device` with a list or
// all): their ray tracer's name with one of these appended, so that their between-run spread is
// modelled apart from lone runs'.
//  - kSweptOnSharedDevice: the device itself ran another sweep at the same time (a list that names
//    it twice; results context.timing_caveat_shared_device): that sweep's work is in its times.
//  - kSweptBesideOthers: other devices of the host were swept at the same time
//    (context.concurrent_with): host and bus contention enter its times.
// Either side of a compare being so gives the rows its class; a shared device wins.
inline constexpr const char* kSweptOnSharedDevice = ", swept on a device shared with another sweep";
inline constexpr const char* kSweptBesideOthers = ", swept beside other devices";
struct RowContext {
  std::string device, tracer;
  double tickA = 0, tickB = 0;
};
CompareRow compareSampleSets(const std::string& variant, const std::string& pass, std::vector<double> a,
                             std::vector<double> b, const CompareOptions& options, const RowContext& context);

}  // namespace hb
