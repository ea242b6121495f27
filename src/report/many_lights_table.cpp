#include "report/many_lights_table.h"

#include <cmath>
#include <map>
#include <sstream>

#include "base/errors.h"
#include "base/text_format.h"
#include "report/results_json.h"

namespace hb {

using nlohmann::json;
using namespace results;  // at, numberAt, medianOf, escapeCell

namespace {

std::string listsOf(const json& run) {
  const json& l = at(at(run, "params"), "light_lists");
  return l.is_string() ? l.get<std::string>() : "tile";
}

}  // namespace

LinearFit fitLine(const std::vector<double>& x, const std::vector<double>& y) {
  HB_ASSERT(x.size() == y.size() && x.size() >= 2);
  const double n = double(x.size());
  double mx = 0, my = 0;
  for (size_t i = 0; i < x.size(); ++i) mx += x[i] / n, my += y[i] / n;
  double sxx = 0, sxy = 0, syy = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
    syy += (y[i] - my) * (y[i] - my);
  }
  LinearFit f;
  f.slope = sxx > 0 ? sxy / sxx : 0.0;
  f.intercept = my - f.slope * mx;
  double ssr = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    const double r = y[i] - (f.intercept + f.slope * x[i]);
    ssr += r * r;
  }
  f.r2 = syy > 0 ? 1.0 - ssr / syy : (ssr == 0 ? 1.0 : 0.0);
  return f;
}

std::string manyLightsTableMarkdown(const json& results) {
  requireResultsFile(results);
  bool any = false;
  for (const json& run : results["runs"]) any = any || listsOf(run) != "tile";
  if (!any) return "";
  std::ostringstream o;
  o << "## Many lights (light lists without a cap)\n\n"
       "GPU times are medians of the measured frames; counts come from the analysis frame. Oracle: the (pixel, "
       "light) pairs no correct culler can skip (range, cone, true normal). Efficiency = oracle / traced (<= 1 "
       "unless pairs were dropped). Dropped: pairs a capped tile list lost. Rays/s: traced rays over the shadow "
       "pass's time. List MB: the grid and the lists (zbin: also the bins, the sorted lights and their order).\n\n"
       "| Run | Lists | Lights | Image | Lights/tile (mean / max) | List MB | Culling (ms) | Shadows (ms) | "
       "Shading (ms) | Frame (ms) | Traced | Oracle | Efficiency | Dropped | G rays/s |\n"
       "|---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  std::map<std::string, std::pair<std::vector<double>, std::vector<double>>> points;  // lists -> (oracle, frame)
  for (const json& run : results["runs"]) {
    if (!at(run, "rays").is_object()) continue;
    const std::string name = at(run, "name").is_string() ? at(run, "name").get<std::string>() : "?";
    const std::string lists = listsOf(run);
    const json& res = at(at(run, "params"), "resolution");
    const std::string image = res.is_array() && res.size() == 2 ? res[0].dump() + "x" + res[1].dump() : "—";
    const json& cul = at(run, "culling");
    const json& rays = at(run, "rays");
    const double traced = numberAt(rays, "traced"), oracle = numberAt(rays, "oracle");
    const double shadows = passMedianMs(run, "shadows"), frame = medianOf(at(run, "frame_ms"));
    const double lights = numberAt(at(run, "params"), "light_count");
    const double listBytes =
        at(cul, "list_memory_bytes").is_number() ? numberAt(cul, "list_memory_bytes") : numberAt(cul, "memory_bytes");
    o << "| " << escapeCell(name) << " | " << lists << " | " << numberCell(lights, "%.0f") << " | " << image << " | "
      << numberCell(numberAt(cul, "lights_per_tile_mean"), "%.1f") << " / "
      << numberCell(numberAt(cul, "lights_per_tile_max"), "%.0f") << " | " << numberCell(listBytes / 1048576.0, "%.2f")
      << " | " << numberCell(passMedianMs(run, "light_culling"), "%.3f") << " | " << numberCell(shadows, "%.2f")
      << " | " << numberCell(passMedianMs(run, "shading"), "%.2f") << " | " << numberCell(frame, "%.2f") << " | "
      << numberCell(traced, "%.0f") << " | " << numberCell(oracle, "%.0f") << " | "
      << numberCell(numberAt(rays, "efficiency"), "%.4f") << " | "
      << numberCell(numberAt(rays, "dropped_by_overflow"), "%.0f") << " | "
      << numberCell(traced / (shadows * 1e-3) / 1e9, "%.2f") << " |\n";
    if (lists != "tile" && !std::isnan(oracle) && !std::isnan(frame)) {
      points[lists + " " + image].first.push_back(oracle);
      points[lists + " " + image].second.push_back(frame);
    }
  }
  if (!points.empty()) {
    o << "\nFrame time against oracle pairs, least squares per list form and image (the cost of a frame is its "
         "rays when R² is near 1 and the intercept small):\n\n"
         "| Lists, image | Runs | ns per oracle pair | Intercept (ms) | R² |\n|---|---:|---:|---:|---:|\n";
    for (const auto& [key, xy] : points) {
      if (xy.first.size() < 2) continue;
      const LinearFit f = fitLine(xy.first, xy.second);
      o << "| " << key << " | " << xy.first.size() << " | " << format("%.3f", f.slope * 1e6) << " | "
        << format("%.2f", f.intercept) << " | " << format("%.4f", f.r2) << " |\n";
    }
  }
  return o.str();
}

}  // namespace hb
