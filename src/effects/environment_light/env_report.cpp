// The environment light's report and table hooks (plan/effect.h EffectDef::report, ::table).
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/effect_report.h"
#include "base/text_format.h"
#include "effects/ambient_occlusion/ao_part.h"
#include "effects/environment_light/env_effect.h"
#include "effects/environment_light/env_part.h"
#include "effects/indirect/indirect_analysis.h"
#include "report/results_json.h"
#include "scene/environment.h"

namespace hb {

namespace {

// Its settings, memory and LDM lists, the light image, and (where the frame has a ray tracer) its
// errors against the same directions ray traced and the Monte Carlo reference on the same surface
// (AoPass::computeWith): the luminance's relative MSE, its total, FLIP (indirect_analysis.h: the
// same measures as the indirect light's, on the same kind of RGB image).
nlohmann::json environmentJson(AoPass& pass, const Scene& scene, uint32_t w, uint32_t h, const ImageWriter& write,
                               std::vector<std::string>& summary) {
  const AoSettings& s = pass.settings().ao;
  nlohmann::json j = s.toJson();
  j.erase("d_max");
  const Environment& env = *scene.environment;
  j["environment"] = toJson(env);
  j["environment"]["image_size"] = {env.width, env.height};
  const std::vector<float> mine = pass.readAo();
  addAoPassFacts(j, pass, mine);
  const float scale = indirectScale(mine);
  j["image_scale"] = scale;
  write("environment.png", indirectToImage(mine, w, h, scale),
        {{"Description", std::string("environment light (") + toString(s.method) +
                             "): (1/pi) integral of L V cos, ACES after x" + std::to_string(scale) +
                             " (its 99th percentile to 1)"}});
  if (!pass.canTrace()) {
    j["errors_not_computed"] = "the frame has no ray tracer (shadows off and method ldm): its references need one";
    return j;
  }
  for (AoMethod ref : {AoMethod::RayTraced, AoMethod::Reference}) {
    const std::string name = std::string("vs_") + toString(ref);
    if (ref == s.method && (ref != AoMethod::Reference || s.isTheReference())) {
      j[name] = {{"rel_mse", 0.0}, {"total_ratio", 1.0}, {"flip", 0.0}, {"itself", true}};
      continue;
    }
    const std::vector<float> r = pass.computeWith(ref);
    const IndirectErrors e = indirectErrors(mine, r, w, h);
    j[name] = toJson(e);
    const float rs = indirectScale(r);
    write(
        "environment_" + std::string(toString(ref)) + ".png", indirectToImage(r, w, h, rs),
        {{"Description", std::string("environment light (") + toString(ref) + "), ACES after x" + std::to_string(rs)}});
    write("environment_error_" + name + ".png", indirectErrorToImage(mine, r, w, h, rs),
          {{"Description",
            std::string("|Y - Y ") + toString(ref) + "| over the reference's 99th percentile, viridis 0..0.5"}});
    char line[200];
    std::snprintf(line, sizeof line, "environment light (%s) vs %s: relMSE %.5f, total %.4f, FLIP %.4f",
                  toString(s.method), toString(ref), e.relMse, e.totalRatio, e.flip);
    summary.push_back(line);
  }
  return j;
}

}  // namespace

void reportEnvironmentLight(EffectReport& r) {
  AoPass* pass = environmentPassOf(r.renderer);
  if (!pass) return;
  const RenderSettings& s = r.renderer.settings();
  r.run[environmentLightEffect().name] = environmentJson(*pass, r.scene, s.width, s.height, r.write, r.summary);
}

std::string environmentTableMarkdown(const nlohmann::json& results) {
  using namespace results;  // at, numberAt, medianOf, escapeCell
  if (!anyRunHas(results, "environment_light")) return "";
  std::ostringstream o;
  o << "## Environment light (layered depth maps, Fig. 11)\n\n"
    << "GPU times are medians of the measured frames; the rest comes from the analysis frame. The value per pixel "
       "is (1/π)∫ L(ω) V(x, ω) cos θ dω. Errors are on its luminance over every pixel: the relative MSE "
       "(Σ(Y − Y_ref)² / ΣY_ref²) and the total (ΣY / ΣY_ref), against the same N directions ray traced (the LDM "
       "approximation alone) and against 1024 stratified cosine-weighted rays (the converged reference: the "
       "direction count too); FLIP of the tone-mapped images against the reference.\n\n"
    << "| Run | Method | N | Map | Image | LDM build (ms) | Environment light (ms) | Frame (ms) | LDM MB | "
       "relMSE vs raytraced | relMSE vs reference | Total vs reference | FLIP vs reference |\n"
    << "|---|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const nlohmann::json& run : results["runs"]) {
    const std::string name = at(run, "name").is_string() ? at(run, "name").get<std::string>() : "?";
    const nlohmann::json& e = at(run, "environment_light");
    const nlohmann::json& res = at(at(run, "params"), "resolution");
    const std::string image = res.is_array() && res.size() == 2 ? res[0].dump() + "x" + res[1].dump() : "—";
    if (!e.is_object()) {
      o << "| " << escapeCell(name) << " | off | — | — | " << image << " | — | — | "
        << numberCell(medianOf(at(run, "frame_ms")), "%.3f") << " | — | — | — | — | — |\n";
      continue;
    }
    const std::string method = at(e, "method").is_string() ? at(e, "method").get<std::string>() : "?";
    const bool ldm = method == "ldm";
    const nlohmann::json& vr = at(e, "vs_raytraced");
    const nlohmann::json& vf = at(e, "vs_reference");
    o << "| " << escapeCell(name) << " | " << method << " | "
      << (method == "reference" ? "—" : numberCell(numberAt(e, "directions"), "%.0f")) << " | "
      << (ldm ? numberCell(numberAt(e, "ldm_resolution"), "%.0f") + "²" : "—") << " | " << image << " | "
      << numberCell(passMedianMs(run, kEnvironmentLdmBuildPass), "%.3f") << " | "
      << numberCell(passMedianMs(run, kEnvironmentLightPass), "%.3f") << " | "
      << numberCell(medianOf(at(run, "frame_ms")), "%.3f") << " | "
      << (ldm ? numberCell(numberAt(at(e, "memory_bytes"), "ldm_links") / 1048576.0, "%.1f") : "—") << " | "
      << (method == "raytraced" ? "0 (itself)" : numberCell(numberAt(vr, "rel_mse"), "%.5f")) << " | "
      << (method == "reference" ? "0 (itself)" : numberCell(numberAt(vf, "rel_mse"), "%.5f")) << " | "
      << (method == "reference" ? "—" : numberCell(numberAt(vf, "total_ratio"), "%.4f")) << " | "
      << (method == "reference" ? "—" : numberCell(numberAt(vf, "flip"), "%.4f")) << " |\n";
  }
  return o.str();
}

}  // namespace hb
