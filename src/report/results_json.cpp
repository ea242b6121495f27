#include "report/results_json.h"

#include <cmath>
#include <limits>
#include <vector>

#include "base/errors.h"
#include "base/text_format.h"
#include "report/stats.h"

namespace hb::results {

const json& at(const json& j, const char* key) {
  static const json kNull;
  return j.is_object() && j.contains(key) ? j[key] : kNull;
}

double numberAt(const json& j, const char* key) {
  const json& v = at(j, key);
  return v.is_number() ? v.get<double>() : std::numeric_limits<double>::quiet_NaN();
}

double medianOf(const json& stats) {
  const double m = numberAt(stats, "median");
  if (std::isfinite(m)) return m;
  std::vector<double> samples;
  for (const json& v : at(stats, "samples"))
    if (v.is_number()) samples.push_back(v.get<double>());
  return samples.empty() ? std::numeric_limits<double>::quiet_NaN() : summarize(samples).median;
}

Timing timingOf(const json& stats) {
  Timing t;
  if (!stats.is_object()) return t;
  if (at(stats, "samples").is_array())
    for (const json& v : at(stats, "samples"))
      if (v.is_number()) t.samples.push_back(v.get<double>());
  if (!t.samples.empty()) {
    const Summary s = summarize(t.samples);
    t.median = s.median;
    t.cv = s.cv;
  } else {
    t.median = numberAt(stats, "median");
    t.cv = numberAt(stats, "cv");
  }
  return t;
}

double passMedianMs(const json& run, const char* pass) {
  const json& passes = at(run, "passes");
  return passes.is_object() && passes.contains(pass) ? medianOf(passes[pass])
                                                     : std::numeric_limits<double>::quiet_NaN();
}

std::string numberCell(double v, const char* fmt) { return std::isnan(v) ? std::string("—") : format(fmt, v); }

void requireResultsFile(const json& r) { requireResultsFile(r, "results"); }

bool anyRunHas(const json& r, const char* key) {
  requireResultsFile(r);
  for (const json& run : r["runs"])
    if (at(run, key).is_object()) return true;
  return false;
}

void requireResultsFile(const json& r, const std::string& source) {
  if (r.is_object() && r.contains("passes_run") && !r.contains("runs"))
    throw InputError(source +
                     ": is a render.json (one frame from 'hybridbench render'), not a results file; pass the "
                     "results.json a 'hybridbench sweep' writes");
  if (!r.is_object() || at(r, "schema_version") != 1 || !at(r, "runs").is_array())
    throw InputError(source +
                     ": not a schema_version 1 results file with a 'runs' array; pass a "
                     "results.json written by 'hybridbench sweep'");
}

std::vector<std::string> timingCaveats(const json& r) {
  std::vector<std::string> out;
  const json& context = at(r, "context");
  for (const char* key : {"timing_caveat", "timing_caveat_shared_device"})
    if (at(context, key).is_string()) out.push_back(at(context, key).get<std::string>());
  // Files written before the caveat was recorded: the device type still says it.
  const json& type = at(at(context, "device"), "type");
  if (out.empty() && type.is_string() && type.get<std::string>() == "cpu")
    out.push_back(
        "measured on a CPU implementation of Vulkan: its per-pass times are not meaningful (its timestamps do not "
        "bracket compute and ray-tracing work); frame times, counts and accuracy are");
  return out;
}

double timestampPeriodMs(const json& r) {
  const json& period = at(at(at(r, "context"), "device"), "timestamp_period_ns");
  return period.is_number() ? period.get<double>() * 1e-6 : 0.0;
}

bool measuredOnCpu(const json& r) {
  const json& type = at(at(at(r, "context"), "device"), "type");
  return (type.is_string() && type.get<std::string>() == "cpu") || at(at(r, "context"), "timing_caveat").is_string();
}

std::string escapeCell(std::string s) {
  for (size_t pos = 0; (pos = s.find('|', pos)) != std::string::npos; pos += 2) s.insert(pos, "\\");
  for (char& ch : s)
    if (ch == '\n') ch = ' ';
  return s;
}

std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char ch : s) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return q + "\"";
}

}  // namespace hb::results
