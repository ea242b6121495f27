// report.html: one self-contained page of a results file (docs/results-format.md) — what a sweep
// found without opening a dozen files. Inline CSS and SVG, no JavaScript, no network: the only
// references out of the page are the variants' images, by path relative to the page's folder.
//
// It holds, top to bottom: a summary (report_summary.h: the fastest and the most accurate variant,
// what accuracy costs in time, the Pareto front); failed variants and warnings (where there are any); the context
// (device, driver, revision, scene, config); with a base file, the comparison B/A (the `compare`
// table and a plot of each ratio with its interval); per pass, the variants' median times as bars
// with a whisker from the 5th to the 95th percentile of their frames; the accuracy-vs-time Pareto
// plot (accuracy_report.h); the roofline plot where the runs carry one (roofline.h); the study's
// tables (all_tables.h); and per variant a <details> with its images side by side.
#pragma once
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "report/compare.h"

namespace hb {

// One image of a variant, as the page shows it.
struct ReportImage {
  std::string href;   // relative to the page's folder, '/'-separated
  std::string label;  // what it is, short ("flip error")
};

struct HtmlReportInput {
  const nlohmann::json* results = nullptr;  // required: a schema-1 results file
  std::string source;                       // what the page names as the results (a path)
  // Each run's images by run name. A run without an entry shows imagesMissing instead.
  std::map<std::string, std::vector<ReportImage>> images;
  std::string imagesMissing =
      "no images beside the results: swept with --no-images, or the results were copied without their variant "
      "folders";
  // With a base: the comparison of results (B) against base (A), as `hybridbench compare` makes it.
  const nlohmann::json* base = nullptr;
  std::string baseSource;
  CompareOptions compareOptions;
};

// The page. Deterministic: the same input gives the same bytes (no time of writing).
// Throws InputError when results (or base) is not a schema-1 results file, or when the two cannot
// be compared (compareResults' rules).
std::string htmlReport(const HtmlReportInput& input);

// The pages' shared <style> element (report.html's, and history's pages: history_html.h).
const char* reportStyle();

// The per-pass bars alone (an inline <svg> per pass), and the B/A plot alone: for the page, and
// for tests that look at one figure.
std::string passBarsSvg(const nlohmann::json& results);
std::string ratioPlotSvg(const CompareReport& report);

}  // namespace hb
