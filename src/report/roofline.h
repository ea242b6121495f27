// A roofline for every timed pass (docs/results-format.md "roofline"): the work a pass did in the
// analysis frame (FramePass::work), divided by its median time, against the device's own peak for
// that unit (gpu/peaks.h). A pass whose work has several units (bytes and triangles, say) is bound
// by the one closest to its peak: that one is its `bound`, the others are listed under `loads`.
#pragma once
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "frame/frame_pass.h"
#include "gpu/peaks.h"

namespace hb {

// The peak per second of each unit: the device's peaks, and for "rays" the rate of the frame's own
// shadow rays traced alone (raybench) where the run has it (0: none).
// Ray units take the rate measured through `backend` (the run's "backend") where it was measured.
std::map<std::string, double> peakRates(const Peaks& peaks, double raybenchRaysPerS, const std::string& backend = "");

// {entry: {bound, work, unit, ms, achieved_per_s, peak_per_s, fraction, source, loads: [...]}} for
// every entry of `works` that has a time in medianMs. fraction is null where no peak was measured
// for any of the entry's units (then bound is its first unit).
nlohmann::json rooflineJson(const std::vector<PassWork>& works, const std::map<std::string, double>& medianMs,
                            const std::map<std::string, double>& peaks);

class Renderer;
// The roofline of a run: the work every pass of the renderer declares (FramePass::work) for the
// analysis frame recorded in `run`, against `peaks` and the run's raybench rate for rays.
nlohmann::json rooflineOf(const Renderer& renderer, const nlohmann::json& run,
                          const std::map<std::string, double>& medianMs, const Peaks& peaks);

// A fraction of a peak as a percentage, "97.1 %". Over 1 a pass ran faster than the peak, so the
// peak measured is not this pass's peak (its work took another path than the peak's kernel: a
// cache, a driver's shortcut, a CPU device's ray rate measured on other rays), and the text says so:
// "116.1 %, over 100 %: not this pass's peak".
std::string peakFractionText(double fraction);
// What a fraction over 100 % means, for captions and legends.
inline constexpr const char* kOverPeakMeaning = "over 100 %: not this pass's peak";

// The units no device peak counts, rated only against measured ceilings (below): the tile pass's
// loop steps, the per-triangle pass's triangles, the resolve's pixels, the splat gather's tests.
bool rateOnlyUnit(const std::string& unit);

// Ceilings measured by the same passes on a ceiling workload (`tables --ceiling FILE`, e.g. a sweep
// of configs/ceilings.json): for the rate-only units (above), the highest rate any run of that file
// reached, per (pass entry, unit, params.primary, params.aa). A run's load in such a unit is then
// rated against it, as against a peak.
struct MeasuredCeiling {
  double perSecond = 0;
  std::string variant;  // the ceiling run that reached it
};
struct MeasuredCeilings {
  std::string file;                              // where they were measured (a path, for the table's words)
  std::map<std::string, MeasuredCeiling> rates;  // by ceilingKey
};
std::string ceilingKey(const std::string& entry, const std::string& unit, const nlohmann::json& params);
MeasuredCeilings measuredCeilings(const nlohmann::json& ceilingResults, const std::string& file);
// How many of a results file's (pass, unit) loads find a ceiling: 0 says the files do not fit.
size_t ceilingMatches(const nlohmann::json& results, const MeasuredCeilings& ceilings);

// The roofline of every run of a results file: a Markdown table (variant, pass, bound, achieved,
// peak, fraction, share of its ceiling, source) and an SVG (achieved against peak on log axes, one
// point per pass and variant, the diagonal = 100 % of the peak).
// With `ceilings`, units no device peak counts are rated against the ceiling runs' rates (above),
// and a column gives each pass's share of its ceiling: the largest of its fractions (its bound's)
// and of the empty dispatch's time over the pass's (peaks dispatch_empty: no dispatch takes less,
// so a pass within a few of it is bound by the launch), with the one that sets it named.
std::string rooflineMarkdown(const nlohmann::json& results, const MeasuredCeilings* ceilings = nullptr);
// The device's peaks of a results file (context.device.peaks) as a Markdown table, each beside the
// vendor's data-sheet figure where this project knows one (memory bandwidth, FP32 on the H100 and
// H200) and the ratio; empty when the file has no peaks.
std::string peaksMarkdown(const nlohmann::json& results);
std::string rooflineSvg(const nlohmann::json& results);

}  // namespace hb
