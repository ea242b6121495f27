#include "effects/ambient_occlusion/ao_part.h"

#include <string>

#include "base/errors.h"
#include "effects/ambient_occlusion/ao_effect.h"
#include "frame/base_parts.h"
#include "frame/pass_work.h"

namespace hb {

AoPart::AoPart(FrameBuilder& f) {
  // The ambient term lights the frame through AO only (scene.h).
  HB_ASSERT(f.scene.ambient);
  f.constants.ambient = glm::vec4(f.scene.ambient->color * f.scene.ambient->intensity, 1.0f);
  const SurfaceInputs surface = surfaceInputs(f);
  AoPassSettings as;
  as.ao = aoSettingsOf(f.value);
  as.worldPos = surface.worldPos;
  as.normals = surface.normals;
  const AoInputs ai = surfaceBindings(f, surface);
  as.tracer = f.tracer;
  const AoPassNames names{ambientOcclusionEffect().name, kLdmBuildPass, "ambient_occlusion.ldm", kAmbientOcclusionPass,
                          kAmbientOcclusionResource};
  FrameLdmSet ldm;
  ao_ = makeFrameAoPass(f, as, ai, names, ldm);
  f.resources.publish(kAmbientOcclusionResource, ao_->output(), "f32 per pixel: AO in [0, 1] (gpu_types.h kAo*)",
                      std::to_string(f.settings.width) + " x " + std::to_string(f.settings.height));
  // A Lambertian surface sends albedo·(1 − metallic)·L_ambient·AO (scene.h Ambient); a pixel
  // without a normal (kAoNoNormal < 0) is unoccluded.
  const glm::vec4 ambient = f.constants.ambient;
  f.resources.addShadingTerm({kAmbientOcclusionResource,
                              ShadingTerm::Storage::FloatPerPixel,
                              {ambient.r, ambient.g, ambient.b},
                              ShadingTerm::Weight::DiffuseAlbedo,
                              1.0f});

  passes_ = aoFramePasses(f, *ao_, surface, names, ldm, skipped_);
}

std::unique_ptr<AoPass> makeFrameAoPass(FrameBuilder& f, const AoPassSettings& settings, const AoInputs& inputs,
                                        const AoPassNames& names, FrameLdmSet& ldm) {
  const AoSettings& ao = settings.ao;
  const LdmSource source = [&](const std::vector<glm::dvec3>& dirs) -> const LdmBuild& {
    ldm = frameLdmSet(f, dirs, ao.ldmResolution, ao.ldmBuild, ao.ldmList, names.effect, names.ldmResource,
                      names.buildPass);
    return *ldm.ldm;
  };
  return std::make_unique<AoPass>(f.ctx, f.scene, settings, f.settings.width, f.settings.height, inputs, source);
}

std::vector<FramePass> aoFramePasses(FrameBuilder& f, AoPass& ao, const SurfaceInputs& surface,
                                     const AoPassNames& names, const FrameLdmSet& ldm,
                                     std::vector<std::pair<std::string, std::string>>& skipped) {
  std::vector<FramePass> passes;
  if (ao.buildsLdms()) addLdmBuildPass(f, ldm, names.buildPass, names.effect, passes, skipped);
  FramePass pass;
  pass.name = names.pass;
  pass.reads = surfaceReads(surface);
  if (ao.buildsLdms()) pass.reads.push_back(ldm.resource);
  if (f.resources.tlas(res::kTlas)) pass.reads.push_back(res::kTlas);
  if (ao.settings().computeBvh()) pass.reads.push_back(res::kTraceBvh);
  pass.writes = {names.output};
  pass.stages = access::kRayStages;
  pass.record = [&ao](VkCommandBuffer cmd, const PassFrame&) { ao.recordAo(cmd); };
  pass.work = [pixels = double(f.settings.width) * f.settings.height, effect = std::string(names.effect),
               name = std::string(names.pass)](const nlohmann::json& a) {
    const nlohmann::json& e = a.contains(effect) ? a[effect] : nlohmann::json::object();
    const double directions = figureAt(e, {"directions"});
    const double lit = pixels - figureAt(e, {"pixels_sky"}) - figureAt(e, {"pixels_without_normal"});
    const std::string method = e.value("method", "");
    WorkItem item;
    if (method == "raytraced")
      item = derived("rays_ao", lit * directions, "one ray per direction per pixel with a surface");
    else if (method == "hbao")
      item = derived("bytes", lit * directions * figureAt(e, {"steps"}) * 4,
                     "a 4 B depth texel per step per direction per pixel (most from cache)");
    else if (method == "gtao")
      item = derived("bytes", lit * directions * figureAt(e, {"steps"}) * 2 * 4,
                     "a 4 B depth texel per step on each side of each slice per pixel (most from cache)");
    else if (method == "reference")
      item = derived("rays_ao", lit * figureAt(e, {"samples"}), "one ray per sample per pixel with a surface");
    else
      item = derived("bytes", lit * directions * 8, "at least one 8 B list node read per direction per pixel");
    return std::vector<PassWork>{{name, {item}}};
  };
  passes.push_back(std::move(pass));
  return passes;
}

AoPass* aoPassOf(const Renderer& renderer) {
  const AoPart* p = renderer.part<AoPart>(ambientOcclusionEffect().name);
  return p ? &p->pass() : nullptr;
}

std::unique_ptr<FramePart> buildAmbientOcclusion(FrameBuilder& frame) { return std::make_unique<AoPart>(frame); }

}  // namespace hb
