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

std::string primaryCoverageCell(const json& primary) {
  const json& c = at(primary, "coverage_check");
  if (!c.is_object()) return "—";
  return numberCell(numberAt(c, "double_covers"), "%.0f") + " / " + numberCell(numberAt(c, "holes"), "%.0f");
}

// a / b as "0.50x" (the Speed-up column's format); "—" unless both are finite and positive (a ray
// cast's paper estimate is 0: it has none, and is not free).
std::string primaryRatioCell(double a, double b) {
  if (!std::isfinite(a) || !std::isfinite(b) || a <= 0 || b <= 0) return "—";
  return numberCell(a / b, "%.2fx");
}

// The reference of the paper's Fig. 9, 2DR brute force: the run whose primary method is "2dr" with
// this run's r3d_thread_box, else the first "2dr" run; nullptr when the results hold none.
const json* reference2dr(const json& runs, const json& run) {
  const json* first = nullptr;
  const json& box = at(at(run, "params"), "r3d_thread_box");
  for (const json& r : runs) {
    if (at(at(r, "primary"), "method") != "2dr") continue;
    if (!box.is_null() && at(at(r, "params"), "r3d_thread_box") == box) return &r;
    if (!first) first = &r;
  }
  return first;
}

// The counters of the columns Nodes visited, Frusta (split) and Culled, absent on results written
// before the BVH methods; since, blocks_culled_early_z is recorded for every compute method (early-z
// of the binned tile pass, r3d_early_z), the others for the BVH methods alone.
constexpr const char* kBvhCounters[] = {
    "bvh_nodes_visited",     "frusta", "frusta_split", "triangles_culled_frustum", "triangles_culled_occlusion",
    "blocks_culled_early_z",
};

// A row that shows them: a BVH method's, or one whose early-z skipped something (a zero early-z
// count alone, as every compute method records, does not bring the columns in).
bool hasBvhCounters(const json& primary) {
  for (const char* key : kBvhCounters)
    if (std::string_view(key) != "blocks_culled_early_z" && !std::isnan(numberAt(primary, key))) return true;
  return numberAt(primary, "blocks_culled_early_z") > 0;
}

// A count with its thousands grouped ("1,234"); "—" for NaN (a missing count).
std::string countCell(double v) {
  if (std::isnan(v)) return "—";
  std::string digits = format("%.0f", std::fabs(v));
  for (int i = int(digits.size()) - 3; i > 0; i -= 3) digits.insert(size_t(i), ",");
  return (v <= -0.5 ? "-" : "") + digits;
}

// Nodes visited | Frusta (split) | Culled: frustum / occlusion / early-z; each "—" when its counts are
// all absent (blocks_culled_early_z is recorded for every compute method, the others for BVH methods).
std::string bvhCells(const json& p) {
  const double frusta = numberAt(p, "frusta"), split = numberAt(p, "frusta_split");
  const double culled[] = {numberAt(p, "triangles_culled_frustum"), numberAt(p, "triangles_culled_occlusion"),
                           numberAt(p, "blocks_culled_early_z")};
  std::string culledCell = "—";
  if (!std::isnan(culled[0]) || !std::isnan(culled[1]) || !std::isnan(culled[2]))
    culledCell = countCell(culled[0]) + " / " + countCell(culled[1]) + " / " + countCell(culled[2]);
  const std::string frustaCell =
      std::isnan(frusta) && std::isnan(split) ? "—" : countCell(frusta) + " (" + countCell(split) + ")";
  return " " + countCell(numberAt(p, "bvh_nodes_visited")) + " | " + frustaCell + " | " + culledCell + " |";
}

}  // namespace

std::string primaryTableMarkdown(const json& results) {
  results::requireResultsFile(results);
  const json& runs = results["runs"];
  double hardwareMs = std::nan("");
  bool anyCompute = false, anyBvh = false;
  for (const json& run : runs) {
    const json& p = at(run, "primary");
    if (!p.is_object()) continue;
    // Every run records its primary method, the hardware prepass too; the table studies the others.
    anyCompute = anyCompute || at(p, "method") != "hardware";
    anyBvh = anyBvh || hasBvhCounters(p);
    if (at(p, "method") == "hardware" && std::isnan(hardwareMs)) hardwareMs = primaryPassMs(run);
  }
  if (!anyCompute) return "";
  const bool have2dr = reference2dr(runs, json()) != nullptr;
  std::ostringstream o;
  o << "## Primary visibility (3D rasterization continuum)\n\n"
    << "Time of the primary-visibility pass (median, GPU timestamps) and the whole frame; the other "
       "columns come from the analysis frame. Speed-up = hardware prepass time / this pass's time. "
       "Time vs 2DR brute force = this pass's time / that of the run with primary=2dr (the one with this run's "
       "r3d_thread_box, else the first), the paper's reference method in Fig. 9 (>1 means slower); the paper's "
       "Fig. 9 ran on a CPU, so these relative times are ours, not the paper's. "
       "Paper ops = the paper's instruction estimate recorded by the run: 57 x setups + 12 x pixels tested for "
       "3DR, 73 and 14 for 2DR's 2D homogeneous rasterization (Davidovic et al. 2012, Fig. 10); results without "
       "it get 57 and 12 for every method. "
       "Paper instr. vs 2DR = this run's paper instruction estimate (paper_scalar_ops_estimate) / that of the "
       "same 2DR brute force run (— for a ray cast, which has no estimate). Double covers / holes: "
       "pixels the method gives to more / fewer triangles than the exact CPU rasterization (every depth; a ray "
       "cast reports one hit per pixel: not counted; holes are not counted, —, for methods that skip hidden "
       "triangles by occlusion culling or early-z). Wrong ids: visible triangle differs from the double ray "
       "cast's, not at a tie. Empty bins: of the (triangle, 8x8 tile) pairs the binned tile pass tested, the "
       "share that covered no pixel (the paper's 18 % of bins refined without a hit, Sect. 3.5).";
  if (anyBvh)
    o << " Nodes visited: the (BVH node, frustum) pairs the BVH traversal tested. Frusta (split): the top-level "
         "frusta and, in parentheses, the splits ((node, frustum) pairs whose frustum was split into four). Culled: "
         "frustum / occlusion / early-z: "
         "triangles culled with a node outside its frustum / with a node behind the depth, and (triangle, 8x8 "
         "block) pairs skipped by early-z.";
  o << " The method names its view when it is not a perspective one.";
  if (!have2dr) o << " These results hold no 2DR brute force run: the columns vs 2DR need a run with primary=2dr.";
  o << "\n\n"
    << "| Run | Method | Primary (ms) | Speed-up vs prepass | Time vs 2DR brute force | Frame (ms) | Setups | "
       "Pixels tested | Edge evals / px | Atomics / px | fp64 fallback | Paper ops (M) | Paper instr. vs 2DR | "
       "Double covers / holes | Wrong ids | Empty bins |"
    << (anyBvh ? " Nodes visited | Frusta (split) | Culled: frustum / occlusion / early-z |" : "") << "\n"
    << "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    << (anyBvh ? "---:|---:|---:|" : "") << "\n";
  for (const json& run : runs) {
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
    // The record's estimate (2DR at the paper's 2D costs); results written before it: 3DR's costs.
    double ops = numberAt(p, "paper_scalar_ops_estimate");
    if (std::isnan(ops)) ops = kPaper3drSetupOps * setups + kPaper3drPixelOps * tested;
    const json* ref = reference2dr(runs, run);
    const std::string vs2drTime = ref ? primaryRatioCell(ms, primaryPassMs(*ref)) : "—";
    const std::string vs2drOps = ref ? primaryRatioCell(numberAt(p, "paper_scalar_ops_estimate"),
                                                        numberAt(at(*ref, "primary"), "paper_scalar_ops_estimate"))
                                     : "—";
    o << "| " << escapeCell(at(run, "name").is_string() ? at(run, "name").get<std::string>() : "?") << " | " << method
      << " | " << numberCell(ms, "%.3f") << " | " << numberCell(hardwareMs / ms, "%.2fx") << " | " << vs2drTime << " | "
      << numberCell(frame, "%.3f") << " | " << numberCell(setups, "%.0f") << " | " << numberCell(tested, "%.0f")
      << " | " << numberCell(numberAt(p, "edge_evaluations_per_pixel"), "%.1f") << " | "
      << numberCell(numberAt(p, "atomics_per_pixel"), "%.2f") << " | "
      << numberCell(100.0 * numberAt(p, "fp64_fallback_rate"), "%.4f %%") << " | " << numberCell(ops * 1e-6, "%.1f")
      << " | " << vs2drOps << " | " << primaryCoverageCell(p) << " | "
      << numberCell(numberAt(at(p, "against_ray_cast"), "not_ties"), "%.0f") << " | " << emptyBins << " |"
      << (anyBvh ? bvhCells(p) : "") << "\n";
  }
  return o.str();
}

}  // namespace hb
