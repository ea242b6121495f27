#include "report/tables.h"
#include "base/numbers.h"
#include "base/text_format.h"
#include "report/results_identity.h"
#include "report/results_json.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <limits>

#include "base/errors.h"
#include "report/stats.h"

namespace hb {

using nlohmann::json;

namespace {

using namespace results;  // at, numberAt, medianOf, escapeCell, csvField, requireResultsFile

struct ThesisConfig {
  const char* table;
  const char* label;
  int tileSize;
  bool lightCulling, aabb;
  const char* normalCulling;
  double thesisMs, thesisDiffPct;
};

// the thesis, Tables 5.1 and 5.2 (RTX 2060 SUPER, 1920x1080, Sponza, 10 point lights).
// "shadow ray culling" is the naive normal reconstruction, "improved" the five-sample one.
const ThesisConfig kThesis[] = {
    {"5.1", "no optimisations", 8, false, false, "off", 16, 0.00},
    {"5.1", "light culling", 8, true, false, "off", 11.52, -28.00},
    {"5.1", "light culling + AABB", 8, true, true, "off", 10.93, -31.69},
    {"5.1", "light culling + AABB + shadow ray culling", 8, true, true, "naive", 9.59, -40.06},
    {"5.1", "light culling + AABB + improved shadow ray culling", 8, true, true, "improved", 9.67, -39.56},
    {"5.1", "improved shadow ray culling", 8, false, false, "improved", 13.55, -15.31},
    {"5.2", "8x8", 8, true, true, "improved", 9.44, kNaN},
    {"5.2", "16x16", 16, true, true, "improved", 9.56, kNaN},
    {"5.2", "32x32", 32, true, true, "improved", 9.99, kNaN},
};

// The thesis's scenes (Sponza in Tables 5.1 and 5.2) have 10 point lights.
constexpr double kThesisLights = 10;

const json& contextLightsOf(const json& results) { return at(at(at(results, "context"), "scene"), "lights"); }

std::string cellNum(double v, const char* fmt) { return std::isfinite(v) ? format(fmt, v) : ""; }

std::string stringAt(const json& j, const char* key) {
  const json& v = at(j, key);
  return v.is_string() ? v.get<std::string>() : v.is_null() ? "unknown" : v.dump();
}

// Median of a stats block: the recorded one, else recomputed from its samples.

// What keeps a run from standing for any row of Tables 5.1/5.2, one short phrase each ("range_test=true",
// "ambient_occlusion on", "1 light"); none for a run of the thesis's frame. The thesis's frame is direct
// light with shadows in a scene of 10 lights: a run that also computed another effect (ambient
// occlusion, indirect or environment light: render.json's "effects" block, or the effect's own key in
// results written before it) is another study's frame; a run with an option beyond the thesis (the
// per-pixel range test, depth slices, a scaled t_min, anti-aliasing, a compute primary) is not the
// thesis's method; a light-count study is the many-lights table's. The light count is the run's scene's
// (runs[].scene.lights), else its light_count, else the results' scene's (results written before either).
std::vector<std::string> beyondThesisFrame(const json& run, const json& contextLights) {
  std::vector<std::string> why;
  const json& effects = at(run, "effects");
  if (effects.is_object())
    for (const auto& [name, state] : effects.items())
      if (name != "shadows" && state.is_object() && state.value("runs", false)) why.push_back(name + " on");
  for (const char* key : {"ambient_occlusion", "indirect", "environment_light"})
    if (at(run, key).is_object() && std::find(why.begin(), why.end(), std::string(key) + " on") == why.end())
      why.push_back(std::string(key) + " on");
  const json& params = at(run, "params");
  auto is = [&](const char* key, auto&& beyond) {
    const json& v = at(params, key);
    if (!v.is_null() && beyond(v))
      why.push_back(std::string(key) + "=" + (v.is_string() ? v.get<std::string>() : v.dump()));
  };
  is("range_test", [](const json& v) { return v == true; });
  is("aa", [](const json& v) { return v != "none"; });
  is("depth_slices", [](const json& v) { return v.is_number() && v.get<double>() != 0; });
  is("t_min", [](const json& v) { return v != "constant"; });
  is("primary", [](const json& v) { return v != "hardware"; });
  json lights = at(at(run, "scene"), "lights");
  if (!lights.is_number()) lights = at(params, "light_count");
  if (!lights.is_number()) lights = contextLights;
  if (lights.is_number() && lights.get<double>() != kThesisLights)
    why.push_back(lights.get<double>() == 1 ? std::string("1 light") : lights.dump() + " lights");
  return why;
}

// Params match a configuration. Without light culling there are no tiles to test against an
// AABB, so the aabb flag is ignored there (aabbExact says whether it matched anyway).
bool paramsMatch(const json& params, const ThesisConfig& c, bool& aabbExact) {
  const json& tile = at(params, "tile_size");
  const json& lc = at(params, "light_culling");
  const json& aabb = at(params, "aabb");
  const json& nc = at(params, "normal_culling");
  if (!tile.is_number_integer() || tile.get<int>() != c.tileSize) return false;
  if (!lc.is_boolean() || lc.get<bool>() != c.lightCulling) return false;
  if (!nc.is_string() || nc.get<std::string>() != c.normalCulling) return false;
  aabbExact = aabb.is_boolean() && aabb.get<bool>() == c.aabb;
  return aabbExact || !c.lightCulling;
}

const json* pickRun(const json& runs, const json& contextLights, const ThesisConfig& c, size_t& matches) {
  const json* best = nullptr;
  int bestScore = -1;
  matches = 0;
  for (const json& run : runs) {
    bool aabbExact = false;
    if (!beyondThesisFrame(run, contextLights).empty() || !paramsMatch(at(run, "params"), c, aabbExact)) continue;
    ++matches;
    // A successful run first; then the run the config named after this row (a config that runs
    // Table 5.1's last row and Table 5.2's 8x8 row apart, with the same parameters, names them so);
    // then an exact AABB flag.
    const int score = (at(run, "status") == "ok" ? 4 : 0) + (at(run, "name") == c.label ? 2 : 0) + (aabbExact ? 1 : 0);
    if (score > bestScore) {  // strict: the first of equals wins
      best = &run;
      bestScore = score;
    }
  }
  return best;
}

std::string bytes(double b) {
  if (!std::isfinite(b)) return "";
  if (b < 1024) return format("%.0f B", b);
  if (b < 1024 * 1024) return format("%.1f KiB", b / 1024);
  return format("%.2f MiB", b / (1024 * 1024));
}

std::string headerLineOf(const json& results) {
  const json& ctx = at(results, "context");
  const json& device = at(ctx, "device");
  const json& scene = at(ctx, "scene");
  const json& tool = at(ctx, "tool");
  const json& res = at(ctx, "resolution");
  const std::string resolution = res.is_array() && res.size() == 2 ? res[0].dump() + "x" + res[1].dump() : "unknown";
  std::string sha = stringAt(scene, "sha256");
  if (sha.size() > 12) sha = sha.substr(0, 12) + "…";
  return "Device: " + stringAt(device, "name") + ", driver " + stringAt(device, "driver") + ", ray tracing " +
         results::tracedBy(results) + " · resolution " + resolution + " · scene " + stringAt(scene, "name") +
         " (sha256 " + sha + ") · hybridbench " + stringAt(tool, "version") + ", git " + stringAt(tool, "git");
}

std::string frameCell(const ThesisRow& r) {
  if (r.status == "missing") return "missing (not in results)";
  if (r.status == "error") return "failed (run '" + r.runName + "')";
  return cellNum(r.frameMs, "%.3f");
}

std::string shareCell(double share) { return cellNum(100 * share, "%.1f %%"); }

}  // namespace

std::vector<ThesisRow> thesisRows(const json& results) {
  requireResultsFile(results);
  const json& runs = results["runs"];
  std::vector<ThesisRow> rows;
  for (const ThesisConfig& c : kThesis) {
    ThesisRow r;
    r.table = c.table;
    r.label = c.label;
    r.tileSize = c.tileSize;
    r.lightCulling = c.lightCulling;
    r.aabb = c.aabb;
    r.normalCulling = c.normalCulling;
    r.thesisMs = c.thesisMs;
    r.thesisDiffPct = c.thesisDiffPct;
    r.frameMs = r.diffPct = r.raysTraced = r.efficiency = r.shadowShare = r.memoryBytes = kNaN;
    size_t matches = 0;
    const json* run = pickRun(runs, contextLightsOf(results), c, matches);
    if (!run) {
      r.status = "missing";
    } else {
      r.runName = at(*run, "name").is_string() ? at(*run, "name").get<std::string>() : "";
      r.status = at(*run, "status") == "ok" ? "ok" : "error";
      if (r.status == "error") r.note = "run '" + r.runName + "' failed: " + stringAt(*run, "error");
      if (matches > 1)
        r.note += (r.note.empty() ? "" : "; ") + format("%zu runs match; showing '%s'", matches, r.runName.c_str());
      if (r.status == "ok") {
        r.frameMs = medianOf(at(*run, "frame_ms"));
        r.raysTraced = numberAt(at(*run, "rays"), "traced");
        r.efficiency = numberAt(at(*run, "rays"), "efficiency");
        r.shadowShare = medianOf(at(at(*run, "passes"), "shadows")) / r.frameMs;
        r.memoryBytes = numberAt(at(*run, "culling"), "memory_bytes");
      }
    }
    rows.push_back(std::move(r));
  }
  // Baselines: "no optimisations" for 5.1, 8x8 for 5.2 (NaN when missing, so the diffs are too).
  const double base51 = rows[0].frameMs, base52 = rows[6].frameMs;
  for (ThesisRow& r : rows) {
    const double base = r.table == "5.1" ? base51 : base52;
    r.diffPct = 100 * (r.frameMs - base) / base;
  }
  return rows;
}

std::string resultsHeaderLine(const json& results) { return headerLineOf(results); }

std::string thesisTablesMarkdown(const json& results) {
  const std::vector<ThesisRow> rows = thesisRows(results);
  std::string out = "# Thesis tables\n\n" + headerLineOf(results) + "\n\n";
  out +=
      "Thesis: RTX 2060 SUPER, 1920x1080, Sponza, 10 point lights (its shadow pass takes ~92 % "
      "of the frame).\n";
  for (const std::string& caveat : timingCaveats(results)) out += "\nCaveat: " + caveat + "\n";
  std::vector<std::string> notes;
  auto extraCells = [&](const ThesisRow& r) {
    if (!r.note.empty()) notes.push_back(r.table + " " + r.label + ": " + r.note);
    return " | " + cellNum(r.raysTraced, "%.0f") + " | " +
           (std::isfinite(r.efficiency) ? formatNear1(r.efficiency) : cellNum(r.efficiency, "%.3f")) + " | " +
           shareCell(r.shadowShare) + " | " + bytes(r.memoryBytes) + " |\n";
  };
  auto diffCell = [](const ThesisRow& r) {
    return r.status != "ok" ? std::string() : std::isfinite(r.diffPct) ? format("%.2f", r.diffPct) : std::string("n/a");
  };
  const std::string extraHeader =
      " | rays traced | ray efficiency (oracle/traced) | shadow pass share | culling memory |\n";
  out += "\n## Table 5.1 — tile size 8x8\n\n";
  out +=
      "| enabled optimisations | frame time (ms) | diff (%) | thesis frame time (ms) | thesis "
      "diff (%)" +
      extraHeader;
  out += "|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const ThesisRow& r : rows) {
    if (r.table != "5.1") continue;
    out += "| " + r.label + " | " + escapeCell(frameCell(r)) + " | " + diffCell(r) + " | " + format("%g", r.thesisMs) +
           " | " + format("%.2f", r.thesisDiffPct) + extraCells(r);
  }
  out +=
      "\n## Table 5.2 — all optimisations on (light culling, AABB, improved shadow ray "
      "culling)\n\n";
  out += "| tile size | frame time (ms) | diff vs 8x8 (%) | thesis frame time (ms)" + extraHeader;
  out += "|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const ThesisRow& r : rows) {
    if (r.table != "5.2") continue;
    out += "| " + r.label + " | " + escapeCell(frameCell(r)) + " | " + diffCell(r) + " | " + format("%g", r.thesisMs) +
           extraCells(r);
  }
  if (!notes.empty()) {
    out += "\nNotes:\n";
    for (const std::string& n : notes) out += "- " + escapeCell(n) + "\n";
  }
  return out;
}

std::string thesisTablesAbsentNote(const json& results) {
  requireResultsFile(results);
  const json& runs = results["runs"];
  const json& contextLights = contextLightsOf(results);
  std::vector<std::pair<std::string, size_t>> reasons;  // in order of first appearance, with their runs
  size_t counted = 0;
  for (const json& run : runs) {
    std::vector<std::string> why = beyondThesisFrame(run, contextLights);
    if (why.empty()) {
      bool aabbExact = false;
      bool row = false;
      for (const ThesisConfig& c : kThesis) row = row || paramsMatch(at(run, "params"), c, aabbExact);
      if (row) continue;  // a row's run after all: the tables are printed
      why.push_back("tile_size, light_culling, aabb and normal_culling of no row");
    }
    ++counted;
    for (const std::string& w : why) {
      auto it = std::find_if(reasons.begin(), reasons.end(), [&](const auto& r) { return r.first == w; });
      if (it == reasons.end())
        reasons.push_back({w, 1});
      else
        ++it->second;
    }
  }
  if (counted < runs.size()) return "";
  std::string list;
  for (const auto& [w, n] : reasons) list += (list.empty() ? "" : ", ") + w + " (" + countOf(n, "run") + ")";
  return "Tables 5.1 and 5.2 (the thesis's) are not printed: they need a run of the thesis's frame (direct light "
         "and shadows alone, 10 lights, hardware depth prepass, no anti-aliasing, range test, depth slices or "
         "scaled t_min), and " +
         std::string(runs.empty() ? "these results have no run." : "no run here is one: " + list + ".") + "\n";
}

std::string thesisTablesCsv(const json& results) {
  const std::vector<ThesisRow> rows = thesisRows(results);
  std::string out =
      "table,configuration,tile_size,light_culling,aabb,normal_culling,status,run,"
      "frame_ms_median,diff_pct,thesis_frame_ms,thesis_diff_pct,rays_traced,ray_efficiency,"
      "shadow_share,culling_memory_bytes,note\n";
  for (const ThesisRow& r : rows) {
    const std::vector<std::string> fields = {r.table,
                                             r.label,
                                             std::to_string(r.tileSize),
                                             r.lightCulling ? "true" : "false",
                                             r.aabb ? "true" : "false",
                                             r.normalCulling,
                                             r.status,
                                             r.runName,
                                             cellNum(r.frameMs, "%.6g"),
                                             cellNum(r.diffPct, "%.2f"),
                                             format("%g", r.thesisMs),
                                             cellNum(r.thesisDiffPct, "%.2f"),
                                             cellNum(r.raysTraced, "%.0f"),
                                             cellNum(r.efficiency, "%.6g"),
                                             cellNum(r.shadowShare, "%.6g"),
                                             cellNum(r.memoryBytes, "%.0f"),
                                             r.note};
    for (size_t i = 0; i < fields.size(); ++i) out += (i ? "," : "") + csvField(fields[i]);
    out += "\n";
  }
  return out;
}

}  // namespace hb
