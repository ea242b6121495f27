#include "report/primary_table.h"

#include <cmath>
#include <sstream>

#include "base/text_format.h"
#include "report/results_json.h"

namespace hb {

using nlohmann::json;
using namespace results;  // at, numberAt, medianOf, escapeCell

namespace {

// The primary-visibility pass of a run: the hardware prepass, rasterization in compute, or ray casting.
double primaryPassMs(const json& run) {
  const json& passes = at(run, "passes");
  for (const char* p : {"depth_prepass", "raster3d", "raycast"})
    if (passes.is_object() && passes.contains(p)) return medianOf(passes[p]);
  return std::nan("");
}

std::string coverageCell(const json& primary) {
  const json& c = at(primary, "coverage_check");
  if (!c.is_object()) return "—";
  return numberCell(numberAt(c, "double_covers"), "%.0f") + " / " + numberCell(numberAt(c, "holes"), "%.0f");
}

}  // namespace

std::string primaryTableMarkdown(const json& results) {
  results::requireResultsFile(results);
  double hardwareMs = std::nan("");
  bool any = false;
  for (const json& run : results["runs"]) {
    const json& p = at(run, "primary");
    if (!p.is_object()) continue;
    any = true;
    if (at(p, "method") == "hardware" && std::isnan(hardwareMs)) hardwareMs = primaryPassMs(run);
  }
  if (!any) return "";
  std::ostringstream o;
  o << "## Primary visibility (3D rasterization continuum)\n\n"
    << "Time of the primary-visibility pass (median, GPU timestamps) and the whole frame; the other "
       "columns come from the analysis frame. Speed-up = hardware prepass time / this pass's time. "
       "Paper ops = 57 x setups + 12 x pixels tested (Davidovic et al. 2012, Fig. 10). Double covers / holes: "
       "pixels the method gives to more / fewer triangles than the exact CPU rasterization (every depth; a ray "
       "cast reports one hit per pixel: not counted). Wrong ids: visible triangle differs from the double ray "
       "cast's, not at a tie. Empty bins: of the (triangle, 8x8 tile) pairs the binned tile pass tested, the "
       "share that covered no pixel (the paper's 18 % of bins refined without a hit, Sect. 3.5). The method "
       "names its view when it is not a perspective one.\n\n"
    << "| Run | Method | Primary (ms) | Speed-up vs prepass | Frame (ms) | Setups | Pixels tested | Edge evals / px | "
       "Atomics / px | fp64 fallback | Paper ops (M) | Double covers / holes | Wrong ids | Empty bins |\n"
    << "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const json& run : results["runs"]) {
    const json& p = at(run, "primary");
    if (!p.is_object()) continue;
    std::string method = at(p, "method").is_string() ? at(p, "method").get<std::string>() : "?";
    if (at(p, "projection").is_string() && at(p, "projection") != "perspective")
      method += " (" + at(p, "projection").get<std::string>() + ")";
    const double refined = numberAt(p, "bins_refined");
    const std::string emptyBins =
        refined > 0 ? numberCell(100.0 * numberAt(p, "bins_refined_without_hit") / refined, "%.1f %%") : "—";
    const double ms = primaryPassMs(run), frame = medianOf(at(run, "frame_ms"));
    const double setups = numberAt(p, "triangle_setups"), tested = numberAt(p, "pixels_tested");
    const double ops = kPaper3drSetupOps * setups + kPaper3drPixelOps * tested;
    o << "| " << escapeCell(at(run, "name").is_string() ? at(run, "name").get<std::string>() : "?") << " | " << method
      << " | " << numberCell(ms, "%.3f") << " | " << numberCell(hardwareMs / ms, "%.2fx") << " | "
      << numberCell(frame, "%.3f") << " | " << numberCell(setups, "%.0f") << " | " << numberCell(tested, "%.0f")
      << " | " << numberCell(numberAt(p, "edge_evaluations_per_pixel"), "%.1f") << " | "
      << numberCell(numberAt(p, "atomics_per_pixel"), "%.2f") << " | "
      << numberCell(100.0 * numberAt(p, "fp64_fallback_rate"), "%.4f %%") << " | " << numberCell(ops * 1e-6, "%.1f")
      << " | " << coverageCell(p) << " | " << numberCell(numberAt(at(p, "against_ray_cast"), "not_ties"), "%.0f")
      << " | " << emptyBins << " |\n";
  }
  return o.str();
}

}  // namespace hb
