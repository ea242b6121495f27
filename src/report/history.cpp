#include "report/history.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <map>
#include <set>
#include <span>
#include <tuple>
#include <utility>

#include "base/errors.h"
#include "base/numbers.h"
#include "base/splitmix64.h"
#include "base/text_format.h"
#include "plan/effects.h"
#include "report/compare.h"
#include "report/results_identity.h"
#include "report/results_json.h"
#include "report/stats.h"

namespace hb {

using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// --- E-divisive -----------------------------------------------------------------------------

// A uniform integer in [0, n) from rng, unbiased: draws at or above the largest multiple of n
// that fits in 64 bits are drawn again (Lemire 2019 discusses faster ways; n here is a few dozen).
uint64_t uniformBelow(SplitMix64& rng, uint64_t n) {
  const uint64_t limit = ~uint64_t(0) - (~uint64_t(0) % n);
  for (;;)
    if (const uint64_t v = rng.next(); v < limit) return v % n;
}

// Fisher-Yates with uniformBelow: the same permutation on every standard library.
void shuffle(std::vector<double>& v, SplitMix64& rng) {
  for (size_t i = v.size(); i > 1; --i) std::swap(v[i - 1], v[uniformBelow(rng, i)]);
}

// --- reading the files ---------------------------------------------------------------------

std::string contextText(const json& j, std::initializer_list<const char*> path) {
  const json* node = &j;
  for (const char* key : path) node = &results::at(*node, key);
  return node->is_string() ? node->get<std::string>() : std::string();
}

std::string resolutionOf(const json& context) {
  const json& r = results::at(context, "resolution");
  if (r.is_array() && r.size() == 2 && r[0].is_number_integer() && r[1].is_number_integer())
    return std::to_string(r[0].get<long long>()) + "x" + std::to_string(r[1].get<long long>());
  return "unknown";
}

std::string knownOrUnknown(std::string s) { return s.empty() ? std::string("unknown") : s; }

// FNV-1a, 64 bits: a fixed hash of text and sample bytes (std::hash differs between libraries).
uint64_t fnv1a(const void* data, size_t size, uint64_t h = 0xcbf29ce484222325ull) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < size; ++i) h = (h ^ p[i]) * 0x100000001b3ull;
  return h;
}

// A pass's place in frame order ("frame" first, then plan/effects.h framePassOrder, a sub-pass
// right after its pass, passes the frame no longer has last).
size_t historyPassRank(const std::vector<std::string>& order, const std::string& p) {
  if (p == "frame") return 0;
  const std::string pass = p.substr(0, p.find('.'));
  const size_t at = size_t(std::find(order.begin(), order.end(), pass) - order.begin());
  return 1 + 2 * at + (pass == p ? 0 : 1);
}

// "02f03e1cb1ac" -> "02f03e1", "677e2708395d-dirty" -> "677e270-dirty": revisions in a table.
std::string shortRevision(const std::string& r) {
  if (r.empty()) return "unknown";
  const size_t dash = r.find('-');
  const std::string hash = r.substr(0, dash);
  return (hash.size() > 7 ? hash.substr(0, 7) : hash) + (dash == std::string::npos ? "" : r.substr(dash));
}

std::string historyCell(double v, const char* fmt) { return std::isfinite(v) ? format(fmt, v) : std::string("n/a"); }

json finiteOrNull(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

double medianOfValues(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return quantileSorted(v, 0.5);
}

// A point being built, with what tells a repeated run (a merged sweep and its parts) apart.
struct PointDraft {
  HistoryPoint point;
  uint64_t samplesHash = 0;
};

// The segments' levels around each change of `changes` (indices into points) and their ratios.
std::vector<HistoryChange> describeChanges(const std::vector<HistoryPoint>& points,
                                           const std::vector<ChangePoint>& changes) {
  std::vector<HistoryChange> out;
  auto levelOf = [&](size_t from, size_t to) {
    std::vector<double> m;
    for (size_t i = from; i < to; ++i) m.push_back(points[i].medianMs);
    return medianOfValues(m);
  };
  for (size_t k = 0; k < changes.size(); ++k) {
    const size_t from = k == 0 ? 0 : changes[k - 1].index;
    const size_t at = changes[k].index;
    const size_t to = k + 1 < changes.size() ? changes[k + 1].index : points.size();
    HistoryChange c;
    c.index = at;
    c.revisionBefore = points[at - 1].revision;
    c.revisionAfter = points[at].revision;
    c.date = points[at].date;
    c.medianBefore = levelOf(from, at);
    c.medianAfter = levelOf(at, to);
    c.ratio = c.medianAfter / c.medianBefore;
    c.p = changes[k].p;
    const std::string &before = points[at - 1].tracer, &after = points[at].tracer;
    if (!before.empty() && !after.empty() && before != after) {
      c.tracerBefore = before;
      c.tracerAfter = after;
    }
    out.push_back(c);
  }
  return out;
}

// The changes beyond the threshold: the smallest change within it is dropped, merging its two
// segments, and the levels are measured again, until every change left exceeds it (as Otava
// filters by magnitude after detection). A significant but small shift then does not split a
// segment that a later, large change is measured against.
std::vector<HistoryChange> changesBeyond(const std::vector<HistoryPoint>& points, std::vector<ChangePoint> changes,
                                         double thresholdPct) {
  const double t = thresholdPct / 100;
  for (;;) {
    std::vector<HistoryChange> described = describeChanges(points, changes);
    size_t smallest = described.size();
    for (size_t k = 0; k < described.size(); ++k) {
      const double r = described[k].ratio;
      if (r > 1 + t || r < 1 - t) continue;
      if (smallest == described.size() || std::fabs(std::log(r)) < std::fabs(std::log(described[smallest].ratio)))
        smallest = k;
    }
    if (smallest == described.size()) return described;
    changes.erase(changes.begin() + std::ptrdiff_t(smallest));
  }
}

void checkOptions(const HistoryOptions& o) {
  if (!(o.alpha > 0 && o.alpha < 1)) throw InputError(format("--alpha %g is outside (0, 1); use e.g. 0.01", o.alpha));
  if (!(o.thresholdPct >= 0))
    throw InputError(format("--threshold %g must be a percentage >= 0, e.g. 5", o.thresholdPct));
  if (o.minSegment < 1) throw InputError("--min-segment 0: a segment holds at least 1 point; use e.g. 2");
  if (o.test == HistoryTest::Welch) {
    if (o.minSegment < 2)
      throw InputError(
          format("--min-segment %zu: Welch's test needs two runs on each side of a change; use 2 or more "
                 "(or --test permutation)",
                 o.minSegment));
    return;
  }
  if (o.permutations < 1) throw InputError("the permutation test needs at least 1 permutation; use e.g. 999");
  // A p-value is at least 1 / (permutations + 1): with fewer permutations no split could pass.
  if (1.0 / double(o.permutations + 1) > o.alpha)
    throw InputError(
        format("--alpha %g is below the smallest p-value %zu permutations can give (1/%zu); raise "
               "--alpha",
               o.alpha, o.permutations, o.permutations + 1));
}

}  // namespace

const char* toString(HistoryTest test) { return test == HistoryTest::Welch ? "welch" : "permutation"; }

std::string historyTestText(const HistoryOptions& o) {
  return o.test == HistoryTest::Welch ? std::string("Welch's t-test of the two sides")
                                      : format("a permutation test (%zu permutations)", o.permutations);
}

// The split of x that maximises Matteson & James's statistic (their eq. 5 with alpha = 1, the
// distance |x - y|, searched over tau and kappa as their E-divisive does):
//   q(tau, kappa) = ab/(a+b) * E,  left part x[0, tau), right part x[tau, kappa), a = tau,
//   b = kappa - tau,
//   E = 2/(ab) sum_{i<tau<=j<kappa} |x_i - x_j| - 2/(a(a-1)) sum_{i<k<tau} |x_i - x_k|
//       - 2/(b(b-1)) sum_{tau<=j<k<kappa} |x_j - x_k|
// (a within-part term is 0 for a part of one value). The change is at tau; kappa lets the right
// part end before the segment does, so that a regression later undone (low, high, low) is seen
// as the step it starts with: with kappa fixed at the segment's end (Otava's simplification) the
// right part would mix the high runs with the low ones after them.
// With P[t][j] = sum_{i<j} |x_i - x_t| (an O(L^2) table), growing the right part by the value t
// adds P[t][tau] to the between sum and P[t][t] - P[t][tau] to the right-within sum, and growing
// the left part by t adds P[t][t] to the left-within sum: every (tau, kappa) costs O(1), a segment
// O(L^2), a permutation test of R permutations O(R L^2).
EnergySplit bestEnergySplit(const std::vector<double>& x, size_t minSegment) {
  const size_t n = x.size();
  EnergySplit best;
  if (n < 2 * minSegment) return best;
  std::vector<std::vector<double>> prefix(n);  // prefix[t][j], j <= t
  for (size_t t = 0; t < n; ++t) {
    prefix[t].assign(t + 1, 0);
    for (size_t j = 0; j < t; ++j) prefix[t][j + 1] = prefix[t][j] + std::fabs(x[j] - x[t]);
  }
  double left = 0;  // sum over pairs within x[0, tau)
  for (size_t tau = 1; tau + minSegment <= n; ++tau) {
    left += prefix[tau - 1][tau - 1];
    if (tau < minSegment) continue;
    const double a = double(tau);
    double between = 0, right = 0;
    for (size_t kappa = tau + 1; kappa <= n; ++kappa) {
      const size_t t = kappa - 1;  // the value that has just joined the right part
      between += prefix[t][tau];
      right += prefix[t][t] - prefix[t][tau];
      if (kappa - tau < minSegment) continue;
      const double b = double(kappa - tau);
      const double e = 2 * between / (a * b) - (tau > 1 ? 2 * left / (a * (a - 1)) : 0) -
                       (kappa - tau > 1 ? 2 * right / (b * (b - 1)) : 0);
      const double q = a * b / (a + b) * e;
      if (q > best.q) {  // the first of equal maxima: deterministic
        const double magnitude = a * b / (a + b) *
                                 (2 * between / (a * b) + (tau > 1 ? 2 * left / (a * (a - 1)) : 0) +
                                  (kappa - tau > 1 ? 2 * right / (b * (b - 1)) : 0));
        best = {tau, q, magnitude, kappa};
      }
    }
  }
  return best;
}

// --- E-divisive: the recursion and the permutation test -------------------------------------------

std::vector<ChangePoint> eDivisive(const std::vector<double>& values, double alpha, size_t permutations,
                                   size_t minSegment, uint64_t seed, HistoryTest test) {
  HB_ASSERT(minSegment >= 1);
  SplitMix64 rng{seed};
  std::vector<size_t> bounds = {0, values.size()};  // segment k is [bounds[k], bounds[k + 1])
  std::vector<ChangePoint> found;
  auto segment = [&](size_t k) {
    return std::vector<double>(values.begin() + std::ptrdiff_t(bounds[k]),
                               values.begin() + std::ptrdiff_t(bounds[k + 1]));
  };
  for (;;) {
    // The candidate: the best split of the segment where it is largest.
    size_t bestSegment = 0;
    EnergySplit best;
    for (size_t k = 0; k + 1 < bounds.size(); ++k)
      if (const EnergySplit s = bestEnergySplit(segment(k), minSegment); s.q > best.q) {
        best = s;
        bestSegment = k;
      }
    if (best.at == 0) break;  // no segment is long enough to split
    const size_t at = bounds[bestSegment] + best.at;
    if (test == HistoryTest::Welch) {
      // The log medians of the candidate's segment on either side of it; a part of one run has no
      // spread to test (Welch needs two a side): such a split is not a change.
      const std::vector<double> all = segment(bestSegment);
      // The right part ends where the statistic's does (kappa): a step later undone is tested as
      // the step, not against the runs after it.
      const std::span<const double> left(all.data(), best.at), right(all.data() + best.at, best.end - best.at);
      const double p = left.size() >= 2 && right.size() >= 2 ? welchT(left, right).p : 1.0;
      if (!(p <= alpha)) break;
      found.push_back({at, p});
      bounds.insert(bounds.begin() + std::ptrdiff_t(bestSegment + 1), at);
      continue;
    }
    // Matteson & James 3.2: the candidate against R permutations in which every segment's values
    // are shuffled within it (the changes found so far stay), each scored by the largest best-split
    // q over the segments, as the candidate was. Under no further change the values within each
    // segment are exchangeable, so p = (1 + #{q_r >= q}) / (1 + R) is a valid p-value:
    // P(p <= alpha) <= alpha. A q_r that equals q in exact arithmetic (the same parts, their
    // values in another order) may differ from it by rounding: each of q's sums adds at most L^2
    // nonnegative distances, so its error is at most L^2 u times its value (u = 2^-53; Higham,
    // "Accuracy and Stability of Numerical Algorithms", 4.2), and q's at most L^2 u times the
    // magnitude of its terms; twice that covers both q and q_r.
    const double longest = double(values.size());
    const double tieTolerance = 2 * longest * longest * 0x1p-53 * best.magnitude;
    size_t atLeast = 0;
    for (size_t r = 0; r < permutations; ++r) {
      double qr = -std::numeric_limits<double>::infinity();
      for (size_t k = 0; k + 1 < bounds.size(); ++k) {
        std::vector<double> v = segment(k);
        if (v.size() < 2 * minSegment) continue;
        shuffle(v, rng);
        qr = std::max(qr, bestEnergySplit(v, minSegment).q);
      }
      if (qr >= best.q - tieTolerance) ++atLeast;
    }
    const double p = double(1 + atLeast) / double(1 + permutations);
    if (p > alpha) break;
    found.push_back({at, p});
    bounds.insert(bounds.begin() + std::ptrdiff_t(bestSegment + 1), at);
  }
  std::sort(found.begin(), found.end(), [](const ChangePoint& a, const ChangePoint& b) { return a.index < b.index; });
  return found;
}

uint64_t historySeriesSeed(uint64_t seed, const HistoryGroup& g, const std::string& variant, const std::string& pass) {
  uint64_t h = fnv1a(&seed, sizeof seed);
  for (const std::string* s : {&g.config, &g.sceneSha256, &g.resolution, &g.device, &variant, &pass}) {
    h = fnv1a(s->data(), s->size(), h);
    h = fnv1a("\0", 1, h);  // "ab"+"c" and "a"+"bc" differ
  }
  // Only where there are overrides, so that a group without any keeps the seed it had before them.
  if (!g.overrides.empty()) h = fnv1a(g.overrides.data(), g.overrides.size(), h);
  return h;
}

// --- finding and grouping the files -----------------------------------------------------------

std::vector<std::string> findResultsFiles(const std::vector<std::string>& paths) {
  std::set<std::string> seen;
  std::vector<std::string> out;
  auto add = [&](const fs::path& p) {
    std::error_code ec;
    const fs::path canonical = fs::weakly_canonical(p, ec);
    if (seen.insert(ec ? p.string() : canonical.string()).second) out.push_back(p.string());
  };
  for (const std::string& path : paths) {
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (!fs::exists(st))
      throw InputError(path +
                       ": no such file or folder; pass results files (results.json, results.json.gz) or "
                       "folders that hold them");
    if (!fs::is_directory(st)) {
      add(path);
      continue;
    }
    std::vector<fs::path> found;
    for (fs::recursive_directory_iterator it(path, fs::directory_options::skip_permission_denied, ec), end;
         !ec && it != end; it.increment(ec)) {
      const std::string name = it->path().filename().string();
      if ((name == "results.json" || name == "results.json.gz") && it->is_regular_file(ec)) found.push_back(it->path());
    }
    if (ec) throw InputError(path + ": cannot be listed (" + ec.message() + "); pass a readable folder");
    if (found.empty())
      throw InputError(path +
                       ": holds no results.json or results.json.gz (searched recursively); pass a folder of "
                       "sweeps, or name files of other names one by one");
    std::sort(found.begin(), found.end());
    for (const fs::path& f : found) add(f);
  }
  return out;
}

std::string groupLabel(const HistoryGroup& g) {
  return g.config + ", " + g.device + ", " + g.resolution + ", scene " + g.sceneSha256.substr(0, 8) +
         (g.overrides.empty() ? "" : ", --set " + g.overrides);
}

namespace {

// context.overrides.set joined by spaces; "" where the sweep had none (or predates the field).
std::string overridesOf(const json& context) {
  const json& sets = results::at(results::at(context, "overrides"), "set");
  std::string out;
  if (!sets.is_array()) return out;
  for (const json& s : sets)
    if (s.is_string()) out += (out.empty() ? "" : " ") + s.get<std::string>();
  return out;
}

HistoryGroup groupOf(const json& results) {
  const json& c = results::at(results, "context");
  return {knownOrUnknown(contextText(c, {"config", "name"})), knownOrUnknown(contextText(c, {"scene", "sha256"})),
          resolutionOf(c), knownOrUnknown(contextText(c, {"device", "name"})), overridesOf(c)};
}

// The files by group (their five fields in order), each held to requireResultsFile.
std::map<std::vector<std::string>, std::vector<const HistoryInput*>> filesByGroup(
    const std::vector<HistoryInput>& inputs) {
  std::map<std::vector<std::string>, std::vector<const HistoryInput*>> byGroup;
  for (const HistoryInput& in : inputs) {
    results::requireResultsFile(in.results, in.path);
    const HistoryGroup g = groupOf(in.results);
    byGroup[{g.config, g.sceneSha256, g.resolution, g.device, g.overrides}].push_back(&in);
  }
  return byGroup;
}

// What a series' points are counted for across groups, for the warnings.
struct HistoryTally {
  size_t repeated = 0;  // runs found again in another file
  size_t cpuFiles = 0;  // files measured on a CPU device
};

// Every timed run of a group's files as a point of its (variant, pass) series, unsorted; the
// variants in first-seen order.
std::map<std::pair<std::string, std::string>, std::vector<PointDraft>> pointsOfGroup(
    const std::vector<const HistoryInput*>& files, std::vector<std::string>& variants, HistoryTally& tally) {
  std::map<std::pair<std::string, std::string>, std::vector<PointDraft>> drafts;
  for (const HistoryInput* in : files) {
    const json& context = results::at(in->results, "context");
    // A CPU device's per-pass times mean nothing (results_json.h measuredOnCpu): its frames only.
    const bool framesOnly = results::measuredOnCpu(in->results);
    const double tickMs = results::timestampPeriodMs(in->results);
    tally.cpuFiles += framesOnly;
    for (const json& run : in->results["runs"]) {
      if (run.value("status", std::string("ok")) != "ok") continue;
      const std::string variant = run.value("name", std::string());
      if (std::find(variants.begin(), variants.end(), variant) == variants.end()) variants.push_back(variant);
      std::string tracer = results::tracerOfRun(run);
      if (tracer.empty()) tracer = contextText(context, {"device", "rt_backend"});
      std::vector<std::pair<std::string, const json*>> timed = {{"frame", &results::at(run, "frame_ms")}};
      if (!framesOnly && results::at(run, "passes").is_object())
        for (auto it = run["passes"].begin(); it != run["passes"].end(); ++it) timed.push_back({it.key(), &*it});
      for (const auto& [pass, stats] : timed) {
        const results::Timing t = results::timingOf(*stats);
        // The log of the median is what E-divisive reads: a time must be positive.
        if (!(t.median > 0) || !std::isfinite(t.median)) continue;
        PointDraft d;
        d.point = {contextText(context, {"tool", "git"}),
                   contextText(context, {"host", "date"}),
                   in->path,
                   tracer,
                   t.median,
                   t.cv,
                   t.samples.size(),
                   sampleResolution(t.samples, tickMs)};
        d.samplesHash = fnv1a(t.samples.data(), t.samples.size() * sizeof(double));
        drafts[{variant, pass}].push_back(std::move(d));
      }
    }
  }
  return drafts;
}

// One series: its points in order, each run once, and its changes.
HistorySeries buildSeries(size_t groupIndex, const HistoryGroup& group, const std::string& variant,
                          const std::string& pass, std::vector<PointDraft> points, const HistoryOptions& options,
                          HistoryTally& tally) {
  std::stable_sort(points.begin(), points.end(), [](const PointDraft& a, const PointDraft& b) {
    return std::tie(a.point.date, a.point.revision, a.point.file) <
           std::tie(b.point.date, b.point.revision, b.point.file);
  });
  HistorySeries s;
  s.group = groupIndex;
  s.variant = variant;
  s.pass = pass;
  // A merged sweep holds its parts' runs again (merge copies them, under the first part's date): a
  // run with the same revision and the same samples, bit for bit, as one already taken is one run,
  // counted once. Hundreds of frame times do not repeat by chance; a file that records a median
  // without samples is never taken for a repeat.
  std::vector<const PointDraft*> kept;
  for (const PointDraft& d : points) {
    const bool again =
        d.point.n > 0 && std::any_of(kept.begin(), kept.end(), [&](const PointDraft* k) {
          return k->samplesHash == d.samplesHash && k->point.n == d.point.n && k->point.revision == d.point.revision;
        });
    if (again) {
      ++tally.repeated;
      continue;
    }
    kept.push_back(&d);
    s.points.push_back(d.point);
  }
  std::vector<double> logs;
  for (const HistoryPoint& p : s.points) logs.push_back(std::log(p.medianMs));
  const std::vector<ChangePoint> found = eDivisive(logs, options.alpha, options.permutations, options.minSegment,
                                                   historySeriesSeed(options.seed, group, variant, pass), options.test);
  s.changes = changesBeyond(s.points, found, options.thresholdPct);
  // Each change's floor, from the points of its two segments (the changes around it bound them).
  for (size_t k = 0; k < s.changes.size(); ++k) {
    const size_t from = k > 0 ? s.changes[k - 1].index : 0;
    const size_t to = k + 1 < s.changes.size() ? s.changes[k + 1].index : s.points.size();
    double resolution = 0;
    for (size_t i = from; i < to; ++i) resolution = std::max(resolution, s.points[i].resolutionMs);
    s.changes[k].floorMs = 2 * resolution;
  }
  if (!s.changes.empty()) {
    const HistoryChange& last = s.changes.back();
    const bool tiny = last.medianBefore < options.minMs && last.medianAfter < options.minMs;
    const bool overFloor = last.medianAfter - last.medianBefore > last.floorMs;
    s.gates = last.ratio > 1 + options.thresholdPct / 100 && !tiny && overFloor;
  }
  return s;
}

// Refuses inputs in which no two files are alike: one file, or files of as many groups.
void requireTwoAlike(const std::vector<HistoryInput>& inputs, size_t alone) {
  if (inputs.empty()) throw InputError("no results files given; pass results files or folders that hold them");
  if (alone < inputs.size()) return;
  const HistoryInput& first = inputs.front();
  if (inputs.size() == 1)
    throw InputError(first.path + ": one results file has no history; pass several runs of one config on one device");
  throw InputError(format("no two of the %zu results files were measured alike (same config name, scene sha256, "
                          "resolution, device name and --set overrides; %s is ",
                          inputs.size(), first.path.c_str()) +
                   groupLabel(groupOf(first.results)) +
                   "); pass runs of one config on one device at several revisions");
}

}  // namespace

HistoryReport buildHistory(const std::vector<HistoryInput>& inputs, const HistoryOptions& options) {
  checkOptions(options);
  HistoryReport report;
  report.options = options;
  report.files = inputs.size();
  const auto byGroup = filesByGroup(inputs);
  size_t alone = 0;
  for (const auto& [key, files] : byGroup) alone += files.size() < 2;
  requireTwoAlike(inputs, alone);
  if (alone > 0)
    report.warnings.push_back(countOf(alone, "file") +
                              " measured unlike any other (config, scene, resolution, device or --set overrides): no "
                              "history, left out");

  const std::vector<std::string> order = framePassOrder();
  HistoryTally tally;
  for (const auto& [key, files] : byGroup) {
    if (files.size() < 2) continue;
    const size_t groupIndex = report.groups.size();
    report.groups.push_back({key[0], key[1], key[2], key[3], key[4]});
    std::vector<std::string> variants;
    std::vector<HistorySeries> groupSeries;
    for (auto& [vp, points] : pointsOfGroup(files, variants, tally))
      groupSeries.push_back(
          buildSeries(groupIndex, report.groups.back(), vp.first, vp.second, std::move(points), options, tally));
    // Variants in the order the files first list them; passes in frame order, "frame" first.
    auto rankOf = [&](const HistorySeries& s) {
      return std::make_pair(size_t(std::find(variants.begin(), variants.end(), s.variant) - variants.begin()),
                            historyPassRank(order, s.pass));
    };
    std::stable_sort(groupSeries.begin(), groupSeries.end(),
                     [&](const HistorySeries& a, const HistorySeries& b) { return rankOf(a) < rankOf(b); });
    for (HistorySeries& s : groupSeries) report.series.push_back(std::move(s));
  }
  if (tally.repeated > 0)
    report.warnings.push_back(countOf(tally.repeated, "time") +
                              " of a run found again in another file (a merged sweep and its parts): counted once");
  if (tally.cpuFiles > 0)
    report.warnings.push_back(countOf(tally.cpuFiles, "file") +
                              " measured on a CPU device: frame times only (its per-pass times are not meaningful)");
  for (const HistorySeries& s : report.series)
    if (s.gates) {
      const HistoryChange& c = s.changes.back();
      report.failures.push_back(s.variant + " / " + s.pass + ": x" + format("%.3f", c.ratio) + " since " +
                                shortRevision(c.revisionAfter) + " (" + report.groups[s.group].config + ", " +
                                report.groups[s.group].device + ")");
    }
  report.regression = !report.failures.empty();
  return report;
}

// --- output --------------------------------------------------------------------------------------

std::string formatHistory(const HistoryReport& r) {
  const HistoryOptions& o = r.options;
  size_t changes = 0, tracerChanges = 0;
  for (const HistorySeries& s : r.series)
    for (const HistoryChange& c : s.changes) {
      ++changes;
      tracerChanges += !c.tracerAfter.empty();
    }
  std::string out = format("history: %zu files, %zu groups, %zu series, %zu changes\n", r.files, r.groups.size(),
                           r.series.size(), changes);
  out += format("E-divisive on log medians: %s, alpha %.4g, min segment %zu\n", historyTestText(o).c_str(), o.alpha,
                o.minSegment);
  out += format("changes within %.4g %% are not reported\n\n", o.thresholdPct);
  if (changes == 0) {
    out += format("no change beyond %.4g %% in any series\n", o.thresholdPct);
  } else {
    out += "| group | variant | pass | revisions | date | median (ms) | ratio | p |\n";
    out += "|---|---|---|---|---|---:|---:|---:|\n";
    for (const HistorySeries& s : r.series)
      for (const HistoryChange& c : s.changes)
        out += "| " + results::escapeCell(groupLabel(r.groups[s.group])) + " | " + results::escapeCell(s.variant) +
               " | " + results::escapeCell(s.pass) + " | " + shortRevision(c.revisionBefore) + " → " +
               shortRevision(c.revisionAfter) + " | " + c.date.substr(0, 10) + " | " +
               historyCell(c.medianBefore, "%.3f") + " → " + historyCell(c.medianAfter, "%.3f") + " | " +
               historyCell(c.ratio, "%.3f") + (c.tracerAfter.empty() ? "" : " *") + " | " + historyCell(c.p, "%.3f") +
               " |\n";
    if (tracerChanges > 0)
      out += format(
          "\n`*`: %zu changes coincide with a change of ray tracer (backend_choice.ran), which they "
          "measure too\n",
          tracerChanges);
  }
  out += format("\nregression (newest segment slower by > %.4g %%): %s\n", o.thresholdPct, r.regression ? "yes" : "no");
  for (const std::string& f : r.failures) out += "- slower: " + f + "\n";
  if (!r.warnings.empty()) {
    out += "\nwarnings:\n";
    for (const std::string& w : r.warnings) out += "- " + w + "\n";
  }
  return out;
}

json toJson(const HistoryReport& r) {
  json groups = json::array();
  for (const HistoryGroup& g : r.groups)
    groups.push_back({{"config", g.config},
                      {"scene_sha256", g.sceneSha256},
                      {"resolution", g.resolution},
                      {"device", g.device},
                      {"overrides", g.overrides}});
  json series = json::array();
  for (const HistorySeries& s : r.series) {
    json points = json::array();
    for (const HistoryPoint& p : s.points)
      points.push_back({{"revision", p.revision},
                        {"date", p.date},
                        {"file", p.file},
                        {"ray_tracing", p.tracer},
                        {"median_ms", p.medianMs},
                        {"cv", finiteOrNull(p.cv)},
                        {"n", p.n},
                        {"resolution_ms", p.resolutionMs}});
    json changes = json::array();
    for (const HistoryChange& c : s.changes)
      changes.push_back({{"index", c.index},
                         {"revision_before", c.revisionBefore},
                         {"revision_after", c.revisionAfter},
                         {"date", c.date},
                         {"median_before_ms", c.medianBefore},
                         {"median_after_ms", c.medianAfter},
                         {"ratio", c.ratio},
                         {"floor_ms", c.floorMs},
                         {"p", c.p},
                         {"ray_tracing_before", c.tracerBefore},
                         {"ray_tracing_after", c.tracerAfter}});
    series.push_back({{"group", s.group},
                      {"variant", s.variant},
                      {"pass", s.pass},
                      {"points", points},
                      {"changes", changes},
                      {"gates", s.gates}});
  }
  const HistoryOptions& o = r.options;
  return {{"schema_version", 1},
          {"method", "e-divisive"},
          {"threshold_pct", o.thresholdPct},
          {"alpha", o.alpha},
          {"test", toString(o.test)},
          {"permutations", o.test == HistoryTest::Permutation ? json(o.permutations) : json(nullptr)},
          {"min_segment", o.minSegment},
          {"min_ms", o.minMs},
          {"seed", o.seed},
          {"files", r.files},
          {"groups", groups},
          {"series", series},
          {"regression", r.regression},
          {"failures", r.failures},
          {"warnings", r.warnings}};
}

}  // namespace hb
