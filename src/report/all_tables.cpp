#include "report/all_tables.h"

#include <algorithm>
#include <cmath>

#include "base/text_format.h"
#include "plan/effects.h"
#include "report/aa_table.h"
#include "report/many_lights_table.h"
#include "report/primary_table.h"
#include "report/results_json.h"
#include "report/tables.h"

namespace hb {

using nlohmann::json;

std::string variantTableMarkdown(const json& results) {
  using namespace results;  // at, numberAt, medianOf, escapeCell
  requireResultsFile(results);
  std::string out =
      "## Runs\n\nNo table of a work this tool reproduces has rows for these runs: each run with its frame time "
      "(median of the measured frames, and the coefficient of variation) and its passes' medians.\n\n"
      "| Run | Status | Frame (ms, median) | CV | Passes (ms, median) |\n|---|---|---:|---:|---|\n";
  for (const json& run : results["runs"]) {
    const std::string name = at(run, "name").is_string() ? at(run, "name").get<std::string>() : "?";
    const std::string status = at(run, "status").is_string() ? at(run, "status").get<std::string>() : "?";
    std::string passes;
    const json& p = at(run, "passes");
    if (p.is_object())
      for (const auto& [pass, stats] : p.items()) {
        if (pass.find('.') != std::string::npos) continue;  // sub-passes: inside their pass
        const double ms = medianOf(stats);
        if (std::isfinite(ms)) passes += (passes.empty() ? "" : ", ") + pass + " " + numberCell(ms, "%.3f");
      }
    out += "| " + escapeCell(name) + " | " + escapeCell(status) + " | " +
           numberCell(medianOf(at(run, "frame_ms")), "%.3f") + " | " +
           numberCell(numberAt(at(run, "frame_ms"), "cv"), "%.4f") + " | " + escapeCell(passes.empty() ? "—" : passes) +
           " |\n";
  }
  return out;
}

std::string builtResourcesTableMarkdown(const json& results) {
  using namespace results;  // at, numberAt, numberCell, escapeCell
  requireResultsFile(results);
  std::string rows;
  for (const json& run : results["runs"]) {
    const json& resources = at(run, "frame_resources");
    if (!resources.is_object()) continue;
    const std::string name = at(run, "name").is_string() ? at(run, "name").get<std::string>() : "?";
    for (const auto& [resource, r] : resources.items()) {
      if (!at(r, "build_ms").is_number()) continue;  // written by a pass, or published by its owner: not built
      const json& by = at(r, "built_by");
      std::string users;
      if (at(r, "users").is_array())
        for (const json& u : r["users"])
          if (u.is_string()) users += (users.empty() ? "" : ", ") + u.get<std::string>();
      rows += "| " + escapeCell(name) + " | " + escapeCell(resource) + " | " +
              escapeCell(by.is_string() ? by.get<std::string>() : "—") + " | " +
              numberCell(numberAt(r, "build_ms"), "%.2f") + " | " +
              numberCell(numberAt(r, "built_bytes") / 1048576.0, "%.2f") + " | " +
              numberCell(numberAt(r, "bytes") / 1048576.0, "%.2f") + " | " + escapeCell(users.empty() ? "—" : users) +
              " |\n";
    }
  }
  if (rows.empty()) return "";
  return "## Built once a frame\n\nWhat the frame builds on the CPU from the scene and the settings (docs/frame.md, "
         "keyed resources): each resource is built once a frame, by the part that first asks for it, and shared by "
         "its users (the passes that read it; raybench where it traced through it). Build: one build's CPU wall "
         "clock, the GPU work it waits for included, not a GPU time. MB built: all of it (a BVH's nodes and "
         "triangles, an LDM set's node pool, maps and counters); MB read: what the frame's passes read of it.\n\n"
         "| Run | Resource | Built by | Build (ms, CPU wall clock) | MB built | MB read | Users |\n"
         "|---|---|---|---:|---:|---:|---|\n" +
         rows;
}

std::string allTablesMarkdown(const json& results) {
  const std::vector<ThesisRow> rows = thesisRows(results);  // throws InputError for a file of another kind
  const bool thesis = std::any_of(rows.begin(), rows.end(), [](const ThesisRow& r) { return r.status != "missing"; });
  std::string out;
  if (thesis) {
    out = thesisTablesMarkdown(results);
  } else {
    out = "# Tables\n\n" + resultsHeaderLine(results) + "\n";
    for (const std::string& caveat : results::timingCaveats(results)) out += "\nCaveat: " + caveat + "\n";
    out += "\n" + thesisTablesAbsentNote(results);
  }
  bool any = thesis;
  auto add = [&](const std::string& table) {
    if (table.empty()) return;
    out += "\n" + table;
    any = true;
  };
  add(primaryTableMarkdown(results));
  add(aaTableMarkdown(results));
  for (const EffectDef* e : allEffects())
    if (e->table) add(e->table(results));
  add(manyLightsTableMarkdown(results));
  if (!any) out += "\n" + variantTableMarkdown(results);
  // Not a study's table (it never stands in for the per-variant one): every study's frame builds.
  const std::string built = builtResourcesTableMarkdown(results);
  if (!built.empty()) out += "\n" + built;
  return out;
}

}  // namespace hb
