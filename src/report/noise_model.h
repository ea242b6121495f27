// The between-run noise of a device (issue #53): how far two runs of the same build, config and
// device model differ, pass by pass, measured on A/A pairs (the same revision swept twice: on two
// GPUs at once, twice at once on one GPU, on two days, whole and in merged parts). `compare --noise FILE` gates a row
// only beyond that spread as well as beyond its threshold; `hybridbench noise` writes the file from the pairs and
// measures its false alarms and what it can detect (docs/usage.md "Between-run noise").
//
// The model, per (device model, ray tracer, pass): d = log(B/A) of each A/A row (compare's
// Hodges-Lehmann ratio), pooled over the config's variants and the pairs; its root mean square
// sigma. A change gates only where log(B/A) > z sigma, z = kNoiseZ: under a normal model of d a
// row of an A/A pair passes that bound with probability 1 - Phi(z) = 0.1 %. The absolute floor of a
// pass (compare.h CompareRow::floorMs) adds z times the root mean square of the A/A pairs' median
// differences in ms over passes under kJitterPassMs: launch jitter, which does not scale with a
// pass's length.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace hb {

// One-sided normal quantile of 0.999: a row of an A/A pair lies beyond z sigma with probability
// 0.1 %; a compare of 45 rows then raises a false alarm with probability at most about 4.4 %.
constexpr double kNoiseZ = 3.0902323061678132;
// Passes under this median on both sides of an A/A row measure launch jitter (the absolute
// floor), not proportional noise: 0.1 ms is 100 timestamp ticks of a 1 ns timer.
constexpr double kJitterPassMs = 0.1;
// Fewer A/A rows than this for a key: its sigma is printed with a warning (sqrt(n) bounds what
// any one row can be in units of the RMS, so a small n cannot show a heavy tail).
constexpr size_t kNoiseFewRows = 8;
// The noise file's schema_version. 2: runs swept on a device shared with another sweep have a key of
// their own (their ray_tracing ends in compare.h's kSweptOnSharedDevice). Version 1 did not set them
// apart (its "swept beside other devices" held them too; before that class, its keys pooled every
// run alone); such a file is refused with the command that rebuilds it.
constexpr int kNoiseSchemaVersion = 2;

struct NoisePass {
  std::string device, tracer, pass;
  size_t n = 0;          // A/A rows pooled
  double rmsLog = 0;     // sigma: RMS of log(B/A)
  double maxAbsLog = 0;  // the largest |log(B/A)| among them
};

struct NoiseJitter {
  std::string device, tracer;
  size_t n = 0;      // A/A rows of passes under kJitterPassMs
  double rmsMs = 0;  // RMS of their median differences, ms
};

struct NoisePairSource {
  std::string a, b;  // the files as named
  std::string device, tracer, revisionA, revisionB, dateA, dateB;
  size_t rows = 0;  // timed rows it gave
};

struct NoiseModel {
  double z = kNoiseZ;
  std::vector<NoisePairSource> pairs;
  std::vector<NoisePass> passes;
  std::vector<NoiseJitter> jitter;
  std::string source;  // the file it was read from ("" when built in memory)

  const NoisePass* find(const std::string& device, const std::string& tracer, const std::string& pass) const;
  const NoiseJitter* jitterOf(const std::string& device, const std::string& tracer) const;
};

struct AaPair {
  nlohmann::json a, b;
  std::string nameA, nameB;
};

// The model of these A/A pairs. Throws InputError (naming the pair) when a pair cannot be compared
// (other scenes or configs) or when its two sides are on different device models: an A/A pair is
// one config swept twice on one model.
NoiseModel buildNoiseModel(const std::vector<AaPair>& pairs);

// The noise file (docs/results-format.md "Noise file") and back. Reading throws InputError naming
// `path` and the field when the file is not one.
nlohmann::json toJson(const NoiseModel& model);
NoiseModel noiseModelFromJson(const nlohmann::json& j, const std::string& path);

// What the model does on its own pairs (`hybridbench noise` prints it).
struct NoiseCheckPair {
  std::string a, b;
  size_t rows = 0;
  size_t gatesWithin = 0;      // compare --gate all, within-run noise only
  size_t gatesModel = 0;       // with the model of every pair (in sample: the pair is in it)
  size_t gatesLeaveOut = 0;    // with the model of the other pairs only
  bool leaveOutCovers = true;  // the other pairs cover this pair's device and tracer
};
struct NoiseDetection {
  std::string device, tracer, pass;
  size_t rows = 0, trials = 0;  // A/A rows over kDetectionMinMs, trials over them all
  double detected = 0;          // the fraction of trials a planted slowdown gated
  double detectedWithin = 0;    // the same, within-run noise only
  double smallest95 = 0;        // the smallest planted slowdown (fraction) gated in >= 95 % of trials
};
struct NoiseCheck {
  double plantedPct = 5, thresholdPct = 5;
  size_t trialsPerRow = 0;
  std::vector<NoiseCheckPair> pairs;
  std::vector<NoiseDetection> detection;
};
// Passes under this median are left out of the detection trials (the "any pass over 0.1 ms").
constexpr double kDetectionMinMs = 0.1;

// False alarms (compare --gate all on each pair, in sample and leaving the pair out) and detection:
// per (device, tracer, pass) over kDetectionMinMs, `trialsPerRow` trials a row, each resampling A's
// and B's frames with replacement (a fixed-seed generator: deterministic) and slowing B's by
// plantedPct. thresholdPct is compare's.
NoiseCheck checkNoiseModel(const std::vector<AaPair>& pairs, const NoiseModel& model, double plantedPct,
                           double thresholdPct, size_t trialsPerRow);

// Markdown: the model per key, then the check.
std::string formatNoise(const NoiseModel& model, const NoiseCheck& check);

}  // namespace hb
