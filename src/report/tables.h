// The thesis's frame-time tables regenerated from a results file (docs/results-format.md),
// with the thesis's own figures (the thesis, Tables 5.1 and 5.2) beside ours:
//   Table 5.1: the six optimisation configurations at 8x8 tiles, diff (%) to "no optimisations";
//   Table 5.2: tile sizes 8/16/32 with light culling, AABB and improved normal culling on.
// Runs are matched by their params, never by their names. A configuration that no run matches is
// printed as "missing (not in results)", never invented.
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace hb {

// One configuration of a thesis table and what the results say about it.
struct ThesisRow {
  std::string table;  // "5.1" or "5.2"
  std::string label;  // "light culling + AABB", "16x16", ...
  int tileSize = 8;
  bool lightCulling = false, aabb = false;
  std::string normalCulling;  // "off" | "naive" | "improved"
  double thesisMs = 0;        // the thesis, Table 5.1 / 5.2
  double thesisDiffPct = 0;   // NaN where the thesis gives none (Table 5.2)

  std::string status;   // "ok", "missing" (no run matches) or "error" (the run failed)
  std::string runName;  // the matched run; empty when missing
  std::string note;     // e.g. the run's error, or "3 runs match; showing 'x'"
  // NaN where the results do not carry the figure:
  double frameMs = 0;      // median frame_ms
  double diffPct = 0;      // 5.1: vs "no optimisations"; 5.2: vs 8x8
  double raysTraced = 0;   // rays.traced
  double efficiency = 0;   // rays.efficiency (oracle / traced)
  double shadowShare = 0;  // median shadows / median frame
  double memoryBytes = 0;  // culling.memory_bytes
};

// Rows of Table 5.1 then Table 5.2, in thesis order. Throws InputError when `results` is not a
// schema-1 results file. When several runs match a configuration, a run with status "ok" is
// preferred, then (without light culling, where the AABB flag has no effect) the one with
// aabb false; the row's note says how many matched. Diff (%) = 100 (t - t_base) / t_base.
std::vector<ThesisRow> thesisRows(const nlohmann::json& results);

// Markdown: a header line (device, driver, resolution, scene, git revision), then both tables
// with our figures, the thesis's, and the extra columns; footnotes for notes.
std::string thesisTablesMarkdown(const nlohmann::json& results);
// The header line alone (device, driver, ray tracing, resolution, scene, revision).
std::string resultsHeaderLine(const nlohmann::json& results);

// Why Tables 5.1 and 5.2 are not printed for these results, as one line naming what keeps each run
// from being the thesis's frame with the runs it applies to ("range_test=true (9 runs)", "1 light (1
// run)"); empty when some run is one of their rows.
std::string thesisTablesAbsentNote(const nlohmann::json& results);

// CSV (RFC 4180): a header, then one row per table row (9), empty cells where a figure is absent.
std::string thesisTablesCsv(const nlohmann::json& results);

}  // namespace hb
