// The ambient-occlusion effect's report hook (plan/effect.h EffectDef::report).
#include <cstdio>
#include <string>
#include <vector>

#include "analysis/effect_report.h"
#include "analysis/ldm_report.h"
#include "effects/ambient_occlusion/ao_analysis.h"
#include "effects/ambient_occlusion/ao_effect.h"
#include "effects/ambient_occlusion/ao_part.h"

namespace hb {

// Ambient occlusion: its settings, memory and LDM lists, the AO image, and (where the frame has a
// ray tracer) its errors against the same directions ray traced and the Monte Carlo reference, on
// the same surface (AoPass::computeWith), each with an error map.
static nlohmann::json aoJson(AoPass& ao, uint32_t w, uint32_t h, const ImageWriter& write,
                             std::vector<std::string>& summary) {
  nlohmann::json a = ao.settings().ao.toJson();
  const std::vector<float> mine = ao.readAo();
  addAoPassFacts(a, ao, mine);
  write("ao.png", aoToImage(mine, w, h),
        {{"Description", std::string("ambient occlusion (") + toString(ao.settings().ao.method) +
                             "): grey = AO, white unoccluded; sky blue; magenta no normal"}});
  if (!ao.canTrace()) {
    a["errors_not_computed"] = "the frame has no ray tracer (shadows off and method ldm): its references need one";
    return a;
  }
  for (AoMethod ref : {AoMethod::RayTraced, AoMethod::Reference}) {
    // The method is its own reference (a reference run at the reference's samples): no error by definition.
    if (ref == ao.settings().ao.method && (ref != AoMethod::Reference || ao.settings().ao.isTheReference())) {
      a[std::string("vs_") + toString(ref)] = {
          {"mae", 0.0}, {"rmse", 0.0}, {"bias", 0.0}, {"flip", 0.0}, {"itself", true}};
      continue;
    }
    const std::vector<float> r = ao.computeWith(ref);
    const AoErrors e = aoErrors(mine, r, w, h);
    const std::string name = std::string("vs_") + toString(ref);
    a[name] = toJson(e);
    write("ao_error_" + name + ".png", aoErrorToImage(mine, r, w, h, 0.25f),
          {{"Description", std::string("|AO - AO ") + toString(ref) + "|, viridis 0..0.25"}});
    char line[200];
    std::snprintf(line, sizeof line,
                  "ambient occlusion (%s) vs %s: MAE %.4f, RMSE %.4f, bias %+.4f, p95 %.4f, FLIP %.4f",
                  toString(ao.settings().ao.method), toString(ref), e.mae, e.rmse, e.bias, e.p95, e.flip);
    summary.push_back(line);
  }
  return a;
}

void addAoPassFacts(nlohmann::json& a, const AoPass& pass, const std::vector<float>& values) {
  const size_t channels = pass.channels();
  uint64_t sky = 0, noNormal = 0;
  for (size_t i = channels - 1; i < values.size(); i += channels) {
    sky += values[i] == gpu::kAoSky;
    noNormal += values[i] == gpu::kAoNoNormal;
  }
  a["pixels_sky"] = sky;
  a["pixels_without_normal"] = noNormal;
  // What traces the raytraced and reference methods' rays (backend=compute: our BVH).
  a["tracer"] = !pass.canTrace()                 ? "none"
                : pass.settings().computeBvh()   ? "compute"
                : pass.context().info().rayQuery ? "rayquery"
                                                 : "pipeline";
  const AoMemory m = pass.memory();
  a["memory_bytes"] = {{"ldm_links", m.ldmLinkBytes},
                       {"ldm_maps", m.ldmMapBytes},
                       {"directions", m.directionBytes},
                       {"output", m.outputBytes},
                       {"total", m.total()}};
  if (m.environmentBytes) a["memory_bytes"]["environment"] = m.environmentBytes;
  if (const LdmBuild* ldm = pass.ldm()) a["ldm"] = ldmJson(*ldm, m.ldmLinkBytes);
}

void reportAmbientOcclusion(EffectReport& r) {
  AoPass* ao = aoPassOf(r.renderer);
  if (!ao) return;
  const RenderSettings& s = r.renderer.settings();
  r.run[ambientOcclusionEffect().name] = aoJson(*ao, s.width, s.height, r.write, r.summary);
}

}  // namespace hb
