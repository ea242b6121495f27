#include "report/compare.h"
#include "base/numbers.h"
#include "base/text_format.h"
#include "report/noise_model.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <limits>
#include <span>

#include "base/errors.h"
#include "base/json_diff.h"
#include "config/config.h"
#include "plan/effects.h"
#include "report/results_identity.h"
#include "report/results_json.h"
#include "report/stats.h"

namespace hb {

using nlohmann::json;

namespace {

// A pass's place in frame order (plan/effects.h framePassOrder: the base frame's passes and
// every effect's), a sub-pass ("raster3d.tiles") right after its pass; passes the frame no longer
// has come last.
size_t passRank(const std::vector<std::string>& order, const std::string& p) {
  const std::string pass = p.substr(0, p.find('.'));
  const size_t at = size_t(std::find(order.begin(), order.end(), pass) - order.begin());
  return 2 * at + (pass == p ? 0 : 1);
}

// The value at a dotted path, or null where any step is missing (never throws).
json valueAt(const json& root, const std::vector<std::string>& path) {
  const json* node = &root;
  for (const std::string& key : path) {
    if (!node->is_object() || !node->contains(key)) return nullptr;
    node = &(*node)[key];
  }
  return *node;
}

std::string shortDump(const json& v) {
  std::string s = v.dump();
  return s.size() > 80 ? s.substr(0, 77) + "..." : s;
}

void requireResultsFile(const json& r, const char* side) {
  if (!r.is_object() || !r.contains("schema_version"))
    throw InputError(
        format("results %s: not a hybridbench results file (no schema_version); "
               "pass a results.json written by 'hybridbench sweep'",
               side));
  if (r["schema_version"] != 1)
    throw InputError(
        format("results %s: schema_version %s is not supported (expected 1); "
               "regenerate it with this version of hybridbench",
               side, shortDump(r["schema_version"]).c_str()));
  if (!r.contains("runs") || !r["runs"].is_array())
    throw InputError(
        format("results %s: field 'runs' is missing or not an array; pass a "
               "complete results.json",
               side));
}

// A results file written before a parameter existed lacks its key; its runs used that parameter's
// default (the behaviour before it was added), so the key is filled in with the default before
// configs are compared.
json withParamDefaults(json variants) {
  if (!variants.is_array()) return variants;
  const json defaults = toJson(VariantParams{});
  for (json& v : variants)
    if (v.is_object() && v.contains("params") && v["params"].is_object())
      for (const auto& [key, value] : defaults.items())
        if (!v["params"].contains(key)) v["params"][key] = value;
  return variants;
}

// What must agree for a comparison to mean anything: the same scene and environment content (their
// sha256s: results_identity.h), the same config, the file paths in it aside. A field that differs is
// named down to its first differing leaf, with both values there; inputs at other paths with the
// same content are one warning that names the paths.
void checkComparable(const json& a, const json& b, const CompareOptions& options, std::vector<std::string>& warnings) {
  const json& contextA = results::at(a, "context");
  const json& contextB = results::at(b, "context");
  std::vector<std::string> differences;
  if (const std::string content = results::contentDifference(contextA, contextB, "A", "B"); !content.empty())
    differences.push_back(content);
  const json configA = results::configIdentity(results::at(contextA, "config"));
  const json configB = results::configIdentity(results::at(contextB, "config"));
  const std::vector<std::pair<std::string, std::pair<json, json>>> fields = {
      {"context.config.scene", {results::at(configA, "scene"), results::at(configB, "scene")}},
      {"context.config.environment", {results::at(configA, "environment"), results::at(configB, "environment")}},
      {"context.resolution", {results::at(contextA, "resolution"), results::at(contextB, "resolution")}},
      {"context.config.resolution", {results::at(configA, "resolution"), results::at(configB, "resolution")}},
      {"context.config.variants",
       {withParamDefaults(results::at(configA, "variants")), withParamDefaults(results::at(configB, "variants"))}},
      {"context.config.sweep", {results::at(configA, "sweep"), results::at(configB, "sweep")}}};
  for (const auto& [name, values] : fields)
    if (const std::optional<JsonDifference> d = firstDifference(values.first, values.second, name))
      differences.push_back(describeDifference(*d, "A", "B"));
  for (const std::string& what : differences) {
    if (!options.force)
      throw InputError("cannot compare: " + what + "; compare runs of the same scene and config, or pass --force");
    warnings.push_back("forced comparison: " + what);
  }
  if (const std::vector<results::MovedInput> moved = results::movedInputs(contextA, contextB); !moved.empty())
    warnings.push_back(results::describeMovedInputs(moved, contextA, differences.empty(), "A", "B"));
}

std::string verdictFor(const CompareRow& r, const CompareOptions& o) {
  const bool significant = r.p < o.alpha;  // false for NaN (no samples)
  const bool noisy = r.nA < kMinSamplesForVerdict || r.nB < kMinSamplesForVerdict || !(r.cvA <= kMaxQuietCv) ||
                     !(r.cvB <= kMaxQuietCv);
  if (noisy && !significant) return "too noisy";
  const double t = o.thresholdPct / 100;
  if (significant && r.ratio > 1 + t) return "slower";
  if (significant && r.ratio < 1 - t) return "faster";
  return "same";
}

}  // namespace

double sampleResolution(std::vector<double> samples, double period) {
  std::sort(samples.begin(), samples.end());
  double step = kNaN;
  for (size_t i = 1; i < samples.size(); ++i)
    if (const double d = samples[i] - samples[i - 1]; d > 0 && !(d >= step)) step = d;
  return std::isfinite(step) ? std::max(step, period) : period;
}

namespace {

// untimed: a side was measured on a CPU device, whose per-pass times mean nothing: those rows get
// "not timed" (no verdict, never a regression); the frame row keeps its verdict.
CompareRow compareTimings(const std::string& variant, const std::string& pass, const results::Timing& ta,
                          const results::Timing& tb, const CompareOptions& o, bool untimed, const RowContext& context) {
  CompareRow r;
  r.variant = variant;
  r.pass = pass;
  r.nA = ta.samples.size();
  r.nB = tb.samples.size();
  r.medianA = ta.median;
  r.medianB = tb.median;
  r.cvA = ta.cv;
  r.cvB = tb.cv;
  r.ratio = tb.median / ta.median;
  r.ciLow = r.ciHigh = r.p = kNaN;
  if (r.nA > 0 && r.nB > 0) {
    r.p = mannWhitneyU(ta.samples, tb.samples).p;
    const RatioInterval ci = ratioInterval(ta.samples, tb.samples, o.alpha);
    if (std::isfinite(ci.estimate)) r.ratio = ci.estimate;  // the interval's own estimator
    r.ciLow = ci.low;
    r.ciHigh = ci.high;
  }
  r.verdict = untimed && pass != "frame" ? "not timed" : verdictFor(r, o);
  r.tracer = context.tracer;
  const NoisePass* between = o.noise ? o.noise->find(context.device, context.tracer, pass) : nullptr;
  const NoiseJitter* jitter = o.noise ? o.noise->jitterOf(context.device, context.tracer) : nullptr;
  const double z = o.noise ? o.noise->z : 0;
  r.floorMs = 2 * std::max(sampleResolution(ta.samples, context.tickA), sampleResolution(tb.samples, context.tickB)) +
              (jitter ? z * jitter->rmsMs : 0);
  if (between) r.bandPct = 100 * (std::exp(z * between->rmsLog) - 1);
  const bool frame = pass == "frame";
  const bool tiny = r.medianA < o.minMs && r.medianB < o.minMs;  // false for NaN
  const bool counted = frame ? o.gate != CompareGate::Passes : o.gate != CompareGate::Frame && !tiny;
  if (r.verdict == "slower") {
    if (between && !(r.ratio > 1 + r.bandPct / 100))
      r.held = format("within the between-run band (+%.3g %%)", r.bandPct);
    else if (!(r.medianB - r.medianA > r.floorMs))
      r.held = format("under the floor (%.3g us)", 1000 * r.floorMs);
  }
  r.gates = r.verdict == "slower" && counted && r.held.empty();
  return r;
}

std::vector<std::string> passesInFrameOrder(const json& passesA, const json& passesB, const std::string& variant,
                                            std::vector<std::string>& warnings) {
  std::vector<std::string> common, extra;
  auto keysOf = [](const json& p) {
    std::vector<std::string> k;
    if (p.is_object())
      for (auto it = p.begin(); it != p.end(); ++it) k.push_back(it.key());
    return k;
  };
  for (const std::string& k : keysOf(passesA)) {
    if (passesB.is_object() && passesB.contains(k))
      common.push_back(k);
    else
      warnings.push_back(variant + ": pass '" + k + "' only in A");
  }
  for (const std::string& k : keysOf(passesB))
    if (!passesA.is_object() || !passesA.contains(k)) warnings.push_back(variant + ": pass '" + k + "' only in B");
  const std::vector<std::string> order = framePassOrder();
  auto rank = [&](const std::string& p) { return passRank(order, p); };
  std::stable_sort(common.begin(), common.end(),
                   [&](const std::string& x, const std::string& y) { return rank(x) < rank(y); });
  return common;  // keys come alphabetically from json, so ties in rank stay alphabetical
}

const json* findRun(const json& runs, const std::string& name) {
  for (const json& run : runs)
    if (run.value("name", std::string()) == name) return &run;
  return nullptr;
}

std::string textAt(const json& r, const std::vector<std::string>& path) {
  const json v = valueAt(r, path);
  return v.is_string() ? v.get<std::string>() : std::string();
}

CompareSide sideOf(const json& r) {
  CompareSide s;
  const std::string name = textAt(r, {"context", "device", "name"});
  if (!name.empty()) s.device = name;
  s.deviceType = textAt(r, {"context", "device", "type"});
  s.driver = textAt(r, {"context", "device", "driver"});
  s.revision = textAt(r, {"context", "tool", "git"});
  s.version = textAt(r, {"context", "tool", "version"});
  s.date = textAt(r, {"context", "host", "date"});
  s.tracer = results::tracedBy(r);
  return s;
}

// VkPhysicalDeviceType as results record it (context.device.type), in words.
std::string kindOf(const std::string& type) {
  if (type == "discrete") return "discrete GPU";
  if (type == "integrated") return "integrated GPU";
  if (type == "virtual") return "virtual GPU";
  if (type == "cpu") return "CPU device";
  return "device of type '" + type + "'";
}

std::string withArticle(const std::string& noun) {
  return (std::string("aeiou").find(noun.front()) != std::string::npos ? "an " : "a ") + noun;
}

// "discrete GPU, driver X, ray tracing compute, hybridbench 0.1.0 at 02f03e1, swept 2026-11-22T07:03:28Z": what the
// file records of its device and build.
std::string describeSide(const CompareSide& s) {
  auto orUnknown = [](const std::string& v) { return v.empty() ? std::string("unknown") : v; };
  return (s.deviceType.empty() ? std::string() : kindOf(s.deviceType) + ", ") + "driver " + orUnknown(s.driver) +
         ", ray tracing " + orUnknown(s.tracer) + ", hybridbench " + orUnknown(s.version) + " at revision " +
         orUnknown(s.revision) + ", swept " + orUnknown(s.date);
}

// Frames with fewer than kFewSamplesWarning samples on a side, one warning per pair of counts that
// names how many variants have it (a CPU device measures 5 frames in every variant: one line).
void warnFewSamples(const std::vector<CompareRow>& rows, std::vector<std::string>& warnings) {
  std::vector<std::pair<std::pair<size_t, size_t>, std::vector<std::string>>> groups;  // in first-seen order
  for (const CompareRow& r : rows) {
    if (r.pass != "frame" || (r.nA >= kFewSamplesWarning && r.nB >= kFewSamplesWarning)) continue;
    const std::pair<size_t, size_t> counts{r.nA, r.nB};
    auto it = std::find_if(groups.begin(), groups.end(), [&](const auto& g) { return g.first == counts; });
    if (it == groups.end()) it = groups.insert(groups.end(), {counts, {}});
    it->second.push_back(r.variant);
  }
  for (const auto& [counts, variants] : groups)
    warnings.push_back(
        (variants.size() == 1 ? "variant '" + variants[0] + "'"
                              : countOf(variants.size(), "variant") + " ('" + variants[0] + "', ...)") +
        format(": only %zu (A) and %zu (B) frame samples; fewer than %zu leaves the U test little power: measure "
               "more frames (sweep --frames N; a CPU device measures 5 unless --frames says otherwise)",
               counts.first, counts.second, kFewSamplesWarning));
}

// Each warning once, in first-seen order; one said n > 1 times ends with "(n times)".
std::vector<std::string> onceEach(const std::vector<std::string>& warnings) {
  std::vector<std::pair<std::string, size_t>> counted;
  for (const std::string& w : warnings) {
    auto it = std::find_if(counted.begin(), counted.end(), [&](const auto& c) { return c.first == w; });
    if (it == counted.end())
      counted.emplace_back(w, 1);
    else
      ++it->second;
  }
  std::vector<std::string> out;
  for (const auto& [w, n] : counted) out.push_back(n > 1 ? w + format(" (%zu times)", n) : w);
  return out;
}

std::string num(double v, const char* fmt) { return std::isfinite(v) ? format(fmt, v) : std::string("n/a"); }

json numOrNull(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

}  // namespace

const char* toString(CompareGate gate) {
  switch (gate) {
    case CompareGate::Frame: return "frame";
    case CompareGate::Passes: return "passes";
    case CompareGate::All: return "all";
  }
  return "?";
}

CompareReport compareResults(const json& a, const json& b, const CompareOptions& options) {
  requireResultsFile(a, "A");
  requireResultsFile(b, "B");
  if (!(options.alpha > 0 && options.alpha < 1))
    throw InputError(format("--alpha %g is outside (0, 1); use e.g. 0.05", options.alpha));
  if (!(options.minMs >= 0))
    throw InputError(format("--min-ms %g must be a time in ms >= 0, e.g. 0.02", options.minMs));
  if (!(options.thresholdPct >= 0))
    throw InputError(format("--threshold %g must be a percentage >= 0, e.g. 5", options.thresholdPct));
  CompareReport report;
  report.a = sideOf(a);
  report.b = sideOf(b);
  report.deviceA = report.a.device;
  report.deviceB = report.b.device;
  report.devicesDifferInKind =
      !report.a.deviceType.empty() && !report.b.deviceType.empty() && report.a.deviceType != report.b.deviceType;
  if (report.devicesDifferInKind)
    report.warnings.push_back("the devices differ in kind: A is " + withArticle(kindOf(report.a.deviceType)) + " (" +
                              report.a.device + "), B is " + withArticle(kindOf(report.b.deviceType)) + " (" +
                              report.b.device + "); B/A measures the two devices, not a change of build");
  report.thresholdPct = options.thresholdPct;
  report.alpha = options.alpha;
  checkComparable(a, b, options, report.warnings);
  for (const auto& [side, r] : {std::pair<const char*, const json*>{"A", &a}, {"B", &b}})
    for (const std::string& caveat : results::timingCaveats(*r))
      report.caveats.push_back(std::string(side) + ": " + caveat);
  const bool untimed = results::measuredOnCpu(a) || results::measuredOnCpu(b);
  if (untimed)
    report.caveats.push_back(
        "per-pass rows measured on a CPU device are \"not timed\": no verdict, never a regression; its frame times "
        "follow the host's load, so an A/A pair on a busy machine can differ beyond the threshold");

  const double tickA = results::timestampPeriodMs(a), tickB = results::timestampPeriodMs(b);
  if (options.noise)
    report.noise = "between-run (" +
                   (options.noise->source.empty() ? std::string("a noise model") : options.noise->source) +
                   format(": %zu A/A pairs)", options.noise->pairs.size());
  const auto besideOthers = [](const json& r) {
    const json& c = r.value("context", json::object());
    return c.contains("concurrent_with") && c["concurrent_with"].is_array() && !c["concurrent_with"].empty();
  };
  const auto onSharedDevice = [](const json& r) {
    return r.value("context", json::object()).contains("timing_caveat_shared_device");
  };
  const char* sweptClass = onSharedDevice(a) || onSharedDevice(b) ? kSweptOnSharedDevice
                           : besideOthers(a) || besideOthers(b)   ? kSweptBesideOthers
                                                                  : "";
  double logRatioSum = 0;
  size_t logRatioCount = 0;
  for (const json& runA : a["runs"]) {
    const std::string name = runA.value("name", std::string());
    const json* runB = findRun(b["runs"], name);
    if (!runB) {
      report.warnings.push_back("variant '" + name + "' only in A");
      continue;
    }
    const std::string statusA = runA.value("status", std::string("ok"));
    const std::string statusB = runB->value("status", std::string("ok"));
    if (statusA != "ok" || statusB != "ok") {
      report.warnings.push_back(
          format("variant '%s' skipped: status %s in A, %s in B", name.c_str(), statusA.c_str(), statusB.c_str()));
      continue;
    }
    const std::string tracerA = results::tracerOfRun(runA), tracerB = results::tracerOfRun(*runB);
    if (!tracerA.empty() && !tracerB.empty() && tracerA != tracerB)
      report.warnings.push_back("variant '" + name + "': traced by " + tracerA + " in A, " + tracerB +
                                " in B (backend_choice.ran); B/A measures the change of ray tracer too");
    // A variant whose GPU was throttled while measured (its telemetry's warning, gpu/telemetry.h).
    for (const auto& [side, run] : {std::pair<const char*, const json*>{"A", &runA}, {"B", runB}})
      if (const std::string w = results::throttleWarningOf(*run); !w.empty())
        report.warnings.push_back("variant '" + name + "' in " + side + ": " + w);
    RowContext context{report.b.device, tracerB.empty() ? textAt(b, {"context", "device", "rt_backend"}) : tracerB,
                       tickA, tickB};
    context.tracer += sweptClass;
    CompareRow frame = compareTimings(name, "frame", results::timingOf(runA.value("frame_ms", json())),
                                      results::timingOf(runB->value("frame_ms", json())), options, untimed, context);
    if (std::isfinite(frame.ratio) && frame.ratio > 0) {
      logRatioSum += std::log(frame.ratio);
      ++logRatioCount;
    }
    report.rows.push_back(std::move(frame));
    const json passesA = runA.value("passes", json::object());
    const json passesB = runB->value("passes", json::object());
    for (const std::string& pass : passesInFrameOrder(passesA, passesB, name, report.warnings))
      report.rows.push_back(compareTimings(name, pass, results::timingOf(passesA[pass]),
                                           results::timingOf(passesB[pass]), options, untimed, context));
  }
  for (const json& runB : b["runs"]) {
    const std::string name = runB.value("name", std::string());
    if (!findRun(a["runs"], name)) report.warnings.push_back("variant '" + name + "' only in B");
  }
  warnFewSamples(report.rows, report.warnings);
  report.warnings = onceEach(report.warnings);
  report.geomeanRatio = logRatioCount ? std::exp(logRatioSum / static_cast<double>(logRatioCount)) : kNaN;
  report.gate = options.gate;
  report.minMs = options.minMs;
  for (const CompareRow& row : report.rows)
    if (row.gates)
      report.failures.push_back(format("%s: %s B/A %s [%s, %s]", row.variant.c_str(), row.pass.c_str(),
                                       num(row.ratio, "%.3f").c_str(), num(row.ciLow, "%.3f").c_str(),
                                       num(row.ciHigh, "%.3f").c_str()));
  report.regression = !report.failures.empty();
  return report;
}

std::string formatCompare(const CompareReport& r) {
  const double confidencePct = 100 * (1 - r.alpha);
  std::string out =
      "A: " + r.a.device + " (" + describeSide(r.a) + ")\nB: " + r.b.device + " (" + describeSide(r.b) + ")\n";
  if (r.devicesDifferInKind) out += "WARNING: " + r.warnings.front() + "\n";
  out += format("threshold %.4g %%, alpha %.4g, gate %s, noise %s", r.thresholdPct, r.alpha, toString(r.gate),
                r.noise.c_str());
  if (r.minMs > 0) out += format(" (passes under %.4g ms on both sides do not gate)", r.minMs);
  out += "\n\n";
  for (const std::string& caveat : r.caveats) out += "caveat: " + caveat + "\n";
  if (!r.caveats.empty()) out += "\n";
  out += format(
      "| variant | pass | A median (ms) | B median (ms) | B/A (Hodges-Lehmann) | %.4g %% CI of B/A | p | "
      "verdict |\n",
      confidencePct);
  out += "|---|---|---:|---:|---:|---|---:|---|\n";
  for (const CompareRow& row : r.rows) {
    const std::string p = !std::isfinite(row.p) ? "n/a" : row.p < 1e-4 ? "<0.0001" : format("%.4f", row.p);
    out += "| " + row.variant + " | " + row.pass + " | " + num(row.medianA, "%.3f") + " | " + num(row.medianB, "%.3f") +
           " | " + num(row.ratio, "%.3f") + " | [" + num(row.ciLow, "%.3f") + ", " + num(row.ciHigh, "%.3f") + "] | " +
           p + " | " + row.verdict + (row.gates ? " (gates)" : "") +
           (row.held.empty() ? "" : " (held: " + row.held + ")") + " |\n";
  }
  out += "\ngeometric mean of frame-time ratios B/A: " + num(r.geomeanRatio, "%.4f") + "\n";
  const char* gated = r.gate == CompareGate::Frame    ? "a frame time"
                      : r.gate == CompareGate::Passes ? "a pass time"
                                                      : "a frame or pass time";
  out += format("regression (%s slower beyond the threshold): %s%s\n", gated, r.regression ? "yes" : "no",
                r.devicesDifferInKind ? " (between devices of different kinds: see the warning above)" : "");
  for (const std::string& f : r.failures) out += "- slower: " + f + "\n";
  if (!r.warnings.empty()) {
    out += "\nwarnings:\n";
    for (const std::string& w : r.warnings) out += "- " + w + "\n";
  }
  return out;
}

std::string formatCompareJunit(const CompareReport& r) {
  size_t failures = 0, skipped = 0;
  for (const CompareRow& row : r.rows) {
    failures += row.gates;
    skipped += row.verdict == "too noisy" || row.verdict == "not timed";
  }
  const std::string counts =
      format("tests=\"%zu\" failures=\"%zu\" errors=\"0\" skipped=\"%zu\"", r.rows.size(), failures, skipped);
  std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out += "<testsuites name=\"hybridbench compare\" " + counts + ">\n";
  out += "  <testsuite name=\"" + escapeXml(r.deviceB + " against " + r.deviceA) + "\" " + counts + ">\n";
  out += "    <properties>\n";
  out += "      <property name=\"device_a\" value=\"" + escapeXml(r.deviceA) + "\"/>\n";
  out += "      <property name=\"device_b\" value=\"" + escapeXml(r.deviceB) + "\"/>\n";
  out += format("      <property name=\"threshold_pct\" value=\"%.4g\"/>\n", r.thresholdPct);
  out += format("      <property name=\"alpha\" value=\"%.4g\"/>\n", r.alpha);
  out += format("      <property name=\"gate\" value=\"%s\"/>\n", toString(r.gate));
  out += format("      <property name=\"min_ms\" value=\"%.4g\"/>\n", r.minMs);
  out += "      <property name=\"noise\" value=\"" + escapeXml(r.noise) + "\"/>\n";
  for (const auto& [side, s] : {std::pair<const char*, const CompareSide*>{"a", &r.a}, {"b", &r.b}})
    for (const auto& [key, value] : {std::pair<const char*, const std::string*>{"device_type", &s->deviceType},
                                     {"driver", &s->driver},
                                     {"revision", &s->revision},
                                     {"version", &s->version},
                                     {"date", &s->date},
                                     {"ray_tracing", &s->tracer}})
      if (!value->empty())
        out += format("      <property name=\"%s_%s\" value=\"", side, key) + escapeXml(*value) + "\"/>\n";
  out += "      <property name=\"geomean_frame_ratio\" value=\"" + num(r.geomeanRatio, "%.4f") + "\"/>\n";
  for (const std::string& w : r.warnings) out += "      <property name=\"warning\" value=\"" + escapeXml(w) + "\"/>\n";
  for (const std::string& c : r.caveats) out += "      <property name=\"caveat\" value=\"" + escapeXml(c) + "\"/>\n";
  out += "    </properties>\n";
  for (const CompareRow& row : r.rows) {
    const std::string what = "B/A " + num(row.ratio, "%.3f") + " (" + num(row.medianB, "%.3f") + " ms against " +
                             num(row.medianA, "%.3f") + " ms), " + format("%.4g", 100 * (1 - r.alpha)) + " % CI [" +
                             num(row.ciLow, "%.3f") + ", " + num(row.ciHigh, "%.3f") + "], p " + num(row.p, "%.4g");
    // time: B's median in seconds (JUnit's unit), 0 when missing.
    out += "    <testcase classname=\"" + escapeXml("hybridbench." + row.variant) + "\" name=\"" + escapeXml(row.pass) +
           "\" time=\"" + format("%.6f", std::isfinite(row.medianB) ? row.medianB / 1000.0 : 0.0) + "\"";
    if (row.gates) {
      out += ">\n      <failure type=\"slower\" message=\"" + escapeXml("slower: " + what) + "\"/>\n    </testcase>\n";
    } else if (row.verdict == "too noisy" || row.verdict == "not timed") {
      out += ">\n      <skipped message=\"" + escapeXml(row.verdict + ": " + what) + "\"/>\n    </testcase>\n";
    } else {
      const std::string verdict = row.verdict != "slower" ? row.verdict
                                  : row.held.empty()
                                      ? "slower, not gated (gate " + std::string(toString(r.gate)) + ", or under " +
                                            format("%.4g", r.minMs) + " ms on both sides)"
                                      : "slower, not gated: " + row.held;
      out += ">\n      <system-out>" + escapeXml(verdict + ": " + what) + "</system-out>\n    </testcase>\n";
    }
  }
  // The suite's own output, after its test cases (the JUnit schema's order): what a CI system shows
  // beside the cases, so that a forced comparison or one across device kinds is never silent.
  if (!r.warnings.empty() || !r.caveats.empty()) {
    std::string text;
    for (const std::string& w : r.warnings) text += "warning: " + w + "\n";
    for (const std::string& c : r.caveats) text += "caveat: " + c + "\n";
    out += "    <system-err>" + escapeXml(text) + "</system-err>\n";
  }
  out += "  </testsuite>\n</testsuites>\n";
  return out;
}

json toJson(const CompareReport& r) {
  json rows = json::array();
  for (const CompareRow& row : r.rows)
    rows.push_back({{"variant", row.variant},
                    {"pass", row.pass},
                    {"n_a", row.nA},
                    {"n_b", row.nB},
                    {"median_a", numOrNull(row.medianA)},
                    {"median_b", numOrNull(row.medianB)},
                    {"cv_a", numOrNull(row.cvA)},
                    {"cv_b", numOrNull(row.cvB)},
                    {"ratio", numOrNull(row.ratio)},
                    {"ci_low", numOrNull(row.ciLow)},
                    {"ci_high", numOrNull(row.ciHigh)},
                    {"p", numOrNull(row.p)},
                    {"verdict", row.verdict},
                    {"gates", row.gates},
                    {"ray_tracing", row.tracer},
                    {"floor_ms", row.floorMs},
                    {"band_pct", numOrNull(row.bandPct)},
                    {"held", row.held}});
  auto side = [](const CompareSide& s) {
    return json{{"device", s.device},     {"device_type", s.deviceType}, {"driver", s.driver},
                {"revision", s.revision}, {"version", s.version},        {"date", s.date},
                {"ray_tracing", s.tracer}};
  };
  return {{"schema_version", 1},
          {"a", side(r.a)},
          {"b", side(r.b)},
          {"devices_differ_in_kind", r.devicesDifferInKind},
          {"device_a", r.deviceA},
          {"device_b", r.deviceB},
          {"threshold_pct", r.thresholdPct},
          {"alpha", r.alpha},
          {"rows", rows},
          {"geomean_ratio", numOrNull(r.geomeanRatio)},
          {"warnings", r.warnings},
          {"caveats", r.caveats},
          {"gate", toString(r.gate)},
          {"min_ms", r.minMs},
          {"noise", r.noise},
          {"failures", r.failures},
          {"regression", r.regression}};
}

CompareRow compareSampleSets(const std::string& variant, const std::string& pass, std::vector<double> a,
                             std::vector<double> b, const CompareOptions& options, const RowContext& context) {
  results::Timing ta, tb;
  ta.samples = std::move(a);
  tb.samples = std::move(b);
  for (results::Timing* t : {&ta, &tb}) {
    const Summary s = summarize(t->samples);
    t->median = s.median;
    t->cv = s.cv;
  }
  return compareTimings(variant, pass, ta, tb, options, false, context);
}

}  // namespace hb
