#include "effects/ambient_occlusion/ao_table.h"

#include <cmath>
#include <sstream>

#include "base/text_format.h"
#include "report/results_json.h"

namespace hb {

using nlohmann::json;
using namespace results;  // at, numberAt, medianOf, escapeCell

std::string aoTableMarkdown(const json& results) {
  if (!anyRunHas(results, "ambient_occlusion")) return "";
  std::ostringstream o;
  o << "## Ambient occlusion (layered depth maps)\n\n"
    << "GPU times are medians of the measured frames; the rest comes from the analysis frame. LDM MB: the lists "
       "as allocated (a 64-bit head per map pixel and a node per fragment, sized by a counting build plus 5 %); "
       "exact: what the fragments need. Nodes / px: mean, p99 and max list length over all map pixels. Errors "
       "are over the pixels with a surface: MAE, and the signed bias (positive: light leaks), against the same N "
       "directions ray traced (the LDM approximation alone) and against 1024 stratified cosine-weighted rays "
       "(the converged reference: the direction count too); FLIP of the AO image against the reference.\n\n"
    << "| Run | Method | N | Map | Image | LDM build (ms) | AO (ms) | Frame (ms) | LDM MB (exact) | Nodes / px | "
       "Overflow | MAE vs raytraced | Bias vs raytraced | MAE vs reference | FLIP vs reference |\n"
    << "|---|---|---:|---:|---|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|\n";
  for (const json& run : results["runs"]) {
    const std::string name = at(run, "name").is_string() ? at(run, "name").get<std::string>() : "?";
    const json& a = at(run, "ambient_occlusion");
    const json& res = at(at(run, "params"), "resolution");
    const std::string image = res.is_array() && res.size() == 2 ? res[0].dump() + "x" + res[1].dump() : "—";
    if (!a.is_object()) {
      o << "| " << escapeCell(name) << " | off | — | — | " << image << " | — | — | "
        << numberCell(medianOf(at(run, "frame_ms")), "%.3f") << " | — | — | — | — | — | — | — |\n";
      continue;
    }
    const std::string method = at(a, "method").is_string() ? at(a, "method").get<std::string>() : "?";
    const bool ldm = method == "ldm";
    const json& l = at(a, "ldm");
    const double mb = numberAt(at(a, "memory_bytes"), "ldm_links") / 1048576.0;
    const std::string nodes = l.is_object() ? numberCell(numberAt(at(l, "nodes_per_pixel"), "mean"), "%.2f") + " / " +
                                                  numberCell(numberAt(at(l, "nodes_per_pixel"), "p99"), "%.0f") +
                                                  " / " + numberCell(numberAt(at(l, "nodes_per_pixel"), "max"), "%.0f")
                                            : "—";
    const json& vr = at(a, "vs_raytraced");
    const json& vf = at(a, "vs_reference");
    o << "| " << escapeCell(name) << " | " << method << " | "
      << (method == "reference" ? "—" : numberCell(numberAt(a, "directions"), "%.0f")) << " | "
      << (ldm ? numberCell(numberAt(a, "ldm_resolution"), "%.0f") + "²" : "—") << " | " << image << " | "
      << numberCell(passMedianMs(run, "ldm_build"), "%.3f") << " | "
      << numberCell(passMedianMs(run, "ambient_occlusion"), "%.3f") << " | "
      << numberCell(medianOf(at(run, "frame_ms")), "%.3f") << " | "
      << (ldm ? numberCell(mb, "%.1f") + " (" + numberCell(numberAt(l, "exact_bytes") / 1048576.0, "%.1f") + ")" : "—")
      << " | " << nodes << " | " << (ldm ? numberCell(numberAt(l, "overflow"), "%.0f") : "—") << " | "
      << (method == "raytraced" ? "0 (itself)" : numberCell(numberAt(vr, "mae"), "%.4f")) << " | "
      << (method == "raytraced" ? "—" : numberCell(numberAt(vr, "bias"), "%+.4f")) << " | "
      << (method == "reference" ? "0 (itself)" : numberCell(numberAt(vf, "mae"), "%.4f")) << " | "
      << (method == "reference" ? "—" : numberCell(numberAt(vf, "flip"), "%.4f")) << " |\n";
  }
  o << "\nThe paper (GTX 780 Ti, 800x800, Crytek Sponza; Figs. 8-10): AO with 512 LDMs of 200x200 in 512.4 ms and "
       "805.5 MB (d_max = 1280 m), of 50x50 in 373.0 ms and 204.1 MB (unattenuated); HBAO (512 directions, up to "
       "128 steps) 903.6 ms; photon tracing for indirect light 2062 ms with 512 LDMs of 200x200. Its memory was "
       "mostly fixed head slots; ours is sized to the fragments.\n";
  return o.str();
}

}  // namespace hb
