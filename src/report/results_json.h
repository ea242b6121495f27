// Reading results files (docs/results-format.md) for the report writers: tolerant lookups that
// turn a missing or mistyped field into null/NaN ("—" in a report, never an invented number).
#pragma once
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace hb::results {

using json = nlohmann::json;

// j[key] when j is an object holding key, else null.
const json& at(const json& j, const char* key);
// j[key] as a number, else NaN.
double numberAt(const json& j, const char* key);
// The median of a stats block: the recorded one, else the median of its samples, else NaN.
double medianOf(const json& stats);
// The samples of a stats block ({median, cv, samples, ...}) and their median and CV. Aggregates are
// recomputed from the samples where present, so that a table and a test on them see the same
// numbers; the recorded median and cv where there are none; NaN where neither is recorded.
// compare and history read times through this.
struct Timing {
  std::vector<double> samples;
  double median = std::numeric_limits<double>::quiet_NaN(), cv = std::numeric_limits<double>::quiet_NaN();
};
Timing timingOf(const json& stats);
// The median GPU time of pass `pass` in a run ("passes": {name: stats}), else NaN.
double passMedianMs(const json& run, const char* pass);
// A table cell: v through printf format fmt, "—" for NaN (a missing figure).
std::string numberCell(double v, const char* fmt);
// Throws InputError unless r is a schema_version 1 results file with a runs array.
void requireResultsFile(const json& r);
// The same, naming the file (source) in the message; a render.json is told apart.
void requireResultsFile(const json& r, const std::string& source);
// Whether some run of a results file (held to requireResultsFile first) has an object under `key`,
// e.g. an effect's record: its table is printed only then.
bool anyRunHas(const json& r, const char* key);
// What the file's context says its times cannot be used for (context.timing_caveat, a CPU
// device's; context.timing_caveat_shared_device, a device two sweeps shared), each one line; a CPU
// device's file written before the caveat was recorded gets the same caveat from its device type.
std::vector<std::string> timingCaveats(const json& r);
// Measured on a CPU device (lavapipe): per-pass times mean nothing there (docs/results-format.md).
bool measuredOnCpu(const json& r);
// The device's timestamp period in ms (context.device.timestamp_period_ns): the finest step a
// pass's times can take; 0 where the file does not record it.
double timestampPeriodMs(const json& r);
// A Markdown table cell: '|' escaped, newlines as spaces.
std::string escapeCell(std::string s);
// A CSV field, quoted (RFC 4180) when it holds a comma, quote or newline.
std::string csvField(const std::string& s);

}  // namespace hb::results
