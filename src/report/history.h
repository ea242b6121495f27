// History of many results files (issue #53): the runs that measure the same thing (same config,
// scene content, resolution and device) as series over time, one per variant and pass, and the
// points where a series changed level, found by E-divisive with a permutation test (Matteson &
// James 2014, "A Nonparametric Approach for Multiple Change Point Analysis of Multivariate Data",
// JASA 109(505); the method Apache Otava, formerly Hunter, runs on CI benchmarks).
#pragma once
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace hb {

// How a candidate split is judged significant. Welch: Welch's t-test of the log medians on either
// side of it (Apache Otava's, formerly Hunter's, choice: deterministic, and a step of a few runs
// in a steady series reaches a small p, which no permutation test of so few runs can).
// Permutation: Matteson & James's permutation test, distribution-free, whose smallest p with n
// runs is bounded below (docs/usage.md "history"): it needs long series.
enum class HistoryTest { Welch, Permutation };
const char* toString(HistoryTest test);
struct HistoryOptions;
// "Welch's t-test of the two sides" or "a permutation test (999 permutations)": for the outputs.
std::string historyTestText(const HistoryOptions& options);

struct HistoryOptions {
  HistoryTest test = HistoryTest::Welch;
  // A change is reported only when the level after it differs from the level before by more than
  // this (as compare's threshold): a shift that is significant but small in a very steady series
  // (0.5 % in a series whose points scatter by 0.1 %) is not one anybody acts on.
  double thresholdPct = 5;
  // Significance level of each permutation test: a split is accepted when its p-value is <= alpha.
  double alpha = 0.01;
  // Random permutations per test. p = (1 + #permutations at least as extreme) / (1 + permutations),
  // so the smallest p is 1 / (permutations + 1): 999 resolves p to 0.001, ten steps below the
  // default alpha.
  size_t permutations = 999;
  // The fewest points a segment may hold. 2: the E-statistic's within-segment term averages over
  // pairs of points, which a single point does not have (Matteson & James need >= 2; their R
  // package ecp defaults to 30), and a one-point segment could never be significant anyway: a
  // permutation puts the lone outlier at either end of n points with chance 2/n, so p >= 2/n, above
  // alpha = 0.01 for every series of fewer than 200 points. The cost: a slower newest run is a
  // change only once a second run confirms it (compare judges one run against another).
  size_t minSegment = 2;
  // A change of a pass whose levels on both sides are under this is reported but never gates, as
  // compare's --min-ms (default 0: each change's own floor, HistoryChange::floorMs, decides).
  double minMs = 0;
  // The permutations' seed; each series mixes in its own key (historySeriesSeed), so a series'
  // result does not depend on which other files were read, or in which order.
  uint64_t seed = 0x68697374'6f727921ull;  // "history!"
};

// One run's time of one pass in one results file.
struct HistoryPoint {
  std::string revision;  // context.tool.git
  std::string date;      // context.host.date (UTC, ISO 8601)
  std::string file;      // the path it was read from
  // The ray tracer that traced (runs[].backend_choice.ran; for files that predate it the device's,
  // context.device.rt_backend), "" when neither is recorded.
  std::string tracer;
  double medianMs = 0;  // the median of its samples (results::timingOf, as compare)
  double cv = 0;        // their coefficient of variation (NaN with one sample)
  size_t n = 0;         // samples
  // The resolution its timestamps gave this pass: the smallest step between two distinct samples,
  // at least the device's timestamp period (compare.h sampleResolution); 0 where neither is known.
  double resolutionMs = 0;
};

// Where a series changed: the points [0, index) and [index, points.size()) of its segments around
// it (the neighbouring change points bound them), "before" and "after".
struct HistoryChange {
  size_t index = 0;
  std::string revisionBefore, revisionAfter;  // of points index - 1 and index
  std::string date;                           // of point index: the first run after the change
  // The median of the segment's point medians (robust to one odd run within a segment).
  double medianBefore = 0, medianAfter = 0;
  double ratio = 1;  // medianAfter / medianBefore: > 1 slower
  // As compare's row floor: twice the coarsest timestamp resolution of the points on either side.
  // A slower change gates only when medianAfter - medianBefore exceeds it.
  double floorMs = 0;
  double p = 1;  // the permutation test's p-value when the split was accepted
  // The ray tracers of points index - 1 and index where both are known and differ: the change
  // then measures the tracer too (compare warns likewise), e.g. backend auto choosing compute.
  std::string tracerBefore, tracerAfter;
};

// What makes runs comparable over time.
struct HistoryGroup {
  std::string config;  // context.config.name
  std::string sceneSha256;
  std::string resolution;  // "1920x1080"
  std::string device;      // context.device.name
  // context.overrides.set, the sweep's --set arguments joined by spaces ("": none): runs of one
  // config under other overrides measure other things, so they make a group of their own.
  std::string overrides;
};

struct HistorySeries {
  size_t group = 0;                    // index into HistoryReport::groups
  std::string variant;                 // runs[].name
  std::string pass;                    // "frame" or a pass name, as compare names them
  std::vector<HistoryPoint> points;    // by date, then revision, then file
  std::vector<HistoryChange> changes;  // ascending index; only those beyond the threshold
  bool gates = false;                  // the newest segment is slower than the one before
};

struct HistoryReport {
  HistoryOptions options;
  size_t files = 0;
  std::vector<HistoryGroup> groups;  // only groups of at least two files
  std::vector<HistorySeries> series;
  std::vector<std::string> warnings;
  bool regression = false;            // some series gates
  std::vector<std::string> failures;  // one short line per series that gates
};

// The results files at `paths`: a file as given (results.json, results.json.gz, or any other name:
// read by content), a folder searched recursively for files named results.json or
// results.json.gz. Each file once, in path order. Throws InputError naming a path that does not
// exist, or a folder that holds no results file.
std::vector<std::string> findResultsFiles(const std::vector<std::string>& paths);

// One loaded results file and the path it came from.
struct HistoryInput {
  std::string path;
  nlohmann::json results;
};

// Groups the files, builds the series and finds their changes. Throws InputError when a file is
// not a schema-1 results file (naming it), when an option is out of range, or when no two files
// are comparable (naming what the files were measured on).
HistoryReport buildHistory(const std::vector<HistoryInput>& inputs, const HistoryOptions& options);

// Change points of `values` (a series in order) by E-divisive: recursive bisection, each split
// the one that maximises the energy statistic q over the current segments (Matteson & James eq. 5,
// the end of the split's right part searched too, as theirs), accepted while its permutation
// p-value is <= alpha. Every segment holds at least minSegment values. Returns the accepted splits
// (the index of the first value after each) ascending, with their p-values. Deterministic: the
// permutations come from SplitMix64(seed).
struct ChangePoint {
  size_t index = 0;
  double p = 1;
};
// test: Welch judges each candidate by Welch's t-test of the log medians on either side of it
// (a side of one value: no change) instead, and ignores permutations and seed.
std::vector<ChangePoint> eDivisive(const std::vector<double>& values, double alpha, size_t permutations,
                                   size_t minSegment, uint64_t seed, HistoryTest test = HistoryTest::Permutation);

// The split of one segment x that maximises the energy statistic q(tau, kappa) of eDivisive (its
// left part x[0, tau), its right part x[tau, kappa), each at least minSegment long; formula in
// history.cpp). at = 0 when x is shorter than 2 * minSegment.
struct EnergySplit {
  size_t at = 0;
  double q = -std::numeric_limits<double>::infinity();  // may be negative: E is an estimate
  // The sum of the magnitudes of q's three terms: what its rounding error scales with.
  double magnitude = 0;
  size_t end = 0;  // kappa: the right part is [at, end)
};
EnergySplit bestEnergySplit(const std::vector<double>& x, size_t minSegment);

// The seed of one series: options.seed mixed with a hash of its group, variant and pass.
uint64_t historySeriesSeed(uint64_t seed, const HistoryGroup& group, const std::string& variant,
                           const std::string& pass);

// The console: one header line of counts and parameters, a Markdown table of the changes, the
// series that gate. Lines stay short (the table's group column is a short label).
std::string formatHistory(const HistoryReport& report);

// history --json: docs/results-format.md#history---json.
nlohmann::json toJson(const HistoryReport& report);

// "thesis, NVIDIA H100 80GB HBM3, 1920x1080, scene 07826db0": a group in a few words.
std::string groupLabel(const HistoryGroup& group);

}  // namespace hb
