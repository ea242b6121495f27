#include "report/aa_table.h"

#include <cmath>

#include "base/text_format.h"
#include "report/results_json.h"

namespace hb {

using nlohmann::json;
using namespace results;  // at, numberAt, medianOf, numberCell, escapeCell

namespace {

// The primary-visibility pass of a run: the hardware prepass, or rasterization in compute.
double primaryMs(const json& run) {
  for (const char* p : {"depth_prepass", "raster3d", "raycast"})
    if (at(at(run, "passes"), p).is_object()) return passMedianMs(run, p);
  return std::nan("");
}

std::string aaOf(const json& run) {
  const json& aa = at(at(run, "params"), "aa");
  return aa.is_string() ? aa.get<std::string>() : "none";
}

// The same variant without anti-aliasing: a run whose params equal this one's but for aa = "none".
const json* baselineOf(const json& runs, const json& run) {
  json mine = at(run, "params");
  if (!mine.is_object()) return nullptr;
  mine.erase("aa");
  for (const json& r : runs) {
    if (aaOf(r) != "none" || at(r, "status") != "ok") continue;
    json theirs = at(r, "params");
    if (!theirs.is_object()) continue;
    theirs.erase("aa");
    if (theirs == mine) return &r;
  }
  return nullptr;
}

std::string ratioCell(double a, double b) {
  if (!std::isfinite(a) || !std::isfinite(b) || a <= 0 || b <= 0) return "—";
  return numberCell(a / b, "%.2fx");
}

// The paper's factor for this mode (Fig. 8), where it gives one.
std::string paperCell(const std::string& aa) {
  if (aa == "msaa16") return "11x";
  if (aa == "csaa-4-12") return "4.3x";
  return "—";
}

std::string coverageCell(const json& run) {
  const json& c = at(at(at(run, "primary"), "aa"), "sample_coverage_check");
  if (!c.is_object()) return "—";
  return numberCell(numberAt(c, "double_covers"), "%.0f") + " / " + numberCell(numberAt(c, "holes"), "%.0f");
}

}  // namespace

std::string aaTableMarkdown(const json& results) {
  const json& runs = at(results, "runs");
  if (!runs.is_array()) return "";
  bool any = false;
  for (const json& run : runs) any = any || aaOf(run) != "none";
  if (!any) return "";
  std::string out =
      "## Anti-aliasing — what accuracy costs in time (3D rasterization paper, Fig. 8)\n\n"
      "| Run | Primary | AA | Frame (ms) | vs no AA | Paper (Fig. 8) | Primary (ms) | vs no AA | of which samples "
      "(ms) | Shading (ms) | Image error (FLIP) | Sample double covers / holes |\n"
      "|---|---|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n";
  std::string reference;
  for (const json& run : runs) {
    const std::string aa = aaOf(run);
    if (!at(run, "params").contains("aa")) continue;
    const json& primary = at(at(run, "params"), "primary");
    out += "| " + escapeCell(at(run, "name").is_string() ? run["name"].get<std::string>() : "?") + " | " +
           escapeCell(primary.is_string() ? primary.get<std::string>() : "?") + " | " + aa;
    if (at(run, "status") != "ok") {
      out += " | failed | | | | | | | | |\n";
      continue;
    }
    const json* base = baselineOf(runs, run);
    const double frame = medianOf(at(run, "frame_ms")), prim = primaryMs(run);
    const double baseFrame = base ? medianOf(at(*base, "frame_ms")) : std::nan("");
    const double basePrim = base ? primaryMs(*base) : std::nan("");
    const json& flip = at(at(run, "accuracy"), "image_error_flip");
    if (reference.empty() && at(flip, "reference").is_string()) reference = flip["reference"].get<std::string>();
    out += " | " + numberCell(frame, "%.3f") + " | " + ratioCell(frame, baseFrame) + " | " + paperCell(aa) + " | " +
           numberCell(prim, "%.3f") + " | " + ratioCell(prim, basePrim) + " | " +
           numberCell(passMedianMs(run, "raster3d.samples"), "%.3f") + " | " +
           numberCell(passMedianMs(run, "shading"), "%.3f") + " | " +
           numberCell(numberAt(at(run, "accuracy"), "image_error"), "%.5f") + " | " + coverageCell(run) + " |\n";
  }
  out +=
      "\nTimes are GPU medians; \"vs no AA\" divides by the same variant with aa none (\"—\" without one). The "
      "paper's factors are its whole frame's, which shades every sample with a shadow and a reflection ray; here "
      "MSAA and CSAA shade once per pixel and distinct triangle, so the frame grows less than the primary pass. "
      "Primary: the hardware depth prepass, or rasterization in compute with its sample planes (\"of which "
      "samples\": the stored samples' planes, rasterized plane by plane; \"—\" where 3dr-binned rasterizes every plane "
      "in one pass, timed as the primary's; hardware MSAA multisamples inside the shading pass). Image error: "
      "mean LDR-FLIP against " +
      (reference.empty() ? std::string("each run's reference") : "the reference (" + reference + ")") +
      ". Sample double covers / holes: each stored sample's coverage against exact CPU rasterization at its "
      "position (\"—\": not counted, as for the pixel centres' coverage check).\n";
  return out;
}

}  // namespace hb
