#include "effects/indirect/indirect_table.h"

#include <cmath>
#include <sstream>

#include "base/text_format.h"
#include "report/results_json.h"

namespace hb {

using nlohmann::json;
using namespace results;  // at, numberAt, medianOf, escapeCell

std::string indirectTableMarkdown(const json& results) {
  if (!anyRunHas(results, "indirect")) return "";
  std::ostringstream o;
  o << "## Indirect light (photons split along layered depth maps)\n\n"
    << "GPU times are medians of the measured frames; the rest comes from the analysis frame. Photons: the split "
       "photons' fixed slots (primaries x N), those splatted, and the share discarded (landed where the camera does "
       "not see, left the scene, or grazing). Errors are on the irradiance's luminance over every pixel: relative "
       "MSE (mean squared error over the reference's mean square), the total light against the reference's (1: as "
       "much light), and FLIP of both tone-mapped alike, against the same photons ray traced (the LDM "
       "approximation alone) and against the gathered reference of as many bounces (the photon method itself). K: "
       "the diffuse bounces (a photon splits into N directions at the first, bounce_directions at the second, "
       "halving after).\n\n"
    << "| Run | Method | K | N | Map | Photons / face | Image | LDM build (ms) | Photon tracing (ms) | Splatting (ms) "
       "| "
       "Frame (ms) | Slots | Splatted | Discarded | MB | relMSE vs raytraced | Total vs raytraced | relMSE vs "
       "reference | Total vs reference | FLIP vs reference |\n"
    << "|---|---|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const json& run : results["runs"]) {
    const json& a = at(run, "indirect");
    if (!a.is_object()) continue;
    const std::string name = at(run, "name").is_string() ? at(run, "name").get<std::string>() : "?";
    const json& res = at(at(run, "params"), "resolution");
    const std::string image = res.is_array() && res.size() == 2 ? res[0].dump() + "x" + res[1].dump() : "—";
    const std::string method = at(a, "method").is_string() ? at(a, "method").get<std::string>() : "?";
    const bool photons = method != "reference";
    // The split photons' tally ("split_photons"; results before it was renamed hold it under "photons",
    // where the setting then stood only in the run's params).
    const json& p = at(a, "split_photons").is_object() ? at(a, "split_photons") : at(a, "photons");
    const double perFace = at(a, "photons").is_number()
                               ? numberAt(a, "photons")
                               : numberAt(at(at(at(run, "params"), "effects"), "indirect"), "photons");
    const json& vr = at(a, "vs_raytraced");
    const json& vf = at(a, "vs_reference");
    const bool selfRt = method == "raytraced", selfRef = method == "reference";
    const double bounces = at(a, "bounces").is_number() ? numberAt(a, "bounces") : 1.0;  // before bounces: 1
    o << "| " << escapeCell(name) << " | " << method << " | " << numberCell(bounces, "%.0f") << " | "
      << (photons ? numberCell(numberAt(a, "directions"), "%.0f") : "—") << " | "
      << (method == "ldm" ? numberCell(numberAt(a, "ldm_resolution"), "%.0f") + "²" : "—") << " | "
      << (photons ? numberCell(perFace, "%.0f") + "²" : "—") << " | " << image << " | "
      << numberCell(passMedianMs(run, "indirect_ldm_build"), "%.3f") << " | "
      << numberCell(passMedianMs(run, photons ? "photon_trace" : "indirect_gather"), "%.3f") << " | "
      << numberCell(passMedianMs(run, "photon_splat"), "%.3f") << " | "
      << numberCell(medianOf(at(run, "frame_ms")), "%.3f") << " | " << numberCell(numberAt(p, "slots"), "%.0f") << " | "
      << numberCell(numberAt(p, "stored"), "%.0f") << " | "
      << numberCell(100.0 * numberAt(p, "discarded_share"), "%.1f %%") << " | "
      << numberCell(numberAt(at(a, "memory_bytes"), "total") / 1048576.0, "%.1f") << " | "
      << (selfRt ? "0 (itself)" : numberCell(numberAt(vr, "rel_mse"), "%.4f")) << " | "
      << (selfRt ? "—" : numberCell(numberAt(vr, "total_ratio"), "%.3f")) << " | "
      << (selfRef ? "0 (itself)" : numberCell(numberAt(vf, "rel_mse"), "%.4f")) << " | "
      << (selfRef ? "—" : numberCell(numberAt(vf, "total_ratio"), "%.3f")) << " | "
      << (selfRef ? "—" : numberCell(numberAt(vf, "flip"), "%.4f")) << " |\n";
  }
  o << "\nThe paper (GTX 780 Ti, 800x800, Crytek Sponza, one spot light; Fig. 10): photon tracing 2062 ms with 512 "
       "LDMs of 200x200 (805.5 MB), splatting the larger share of the frame.\n";
  return o.str();
}

}  // namespace hb
