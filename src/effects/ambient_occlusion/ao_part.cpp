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
  if (f.settings.backend == RtBackend::Compute && ai.tlas) as.computeBvh = f.traceBvh;  // traces through our BVH
  ao_ = std::make_unique<AoPass>(f.ctx, f.gpuScene, f.scene, as, f.settings.width, f.settings.height, ai);
  f.resources.publish(res::kAmbientOcclusion, ao_->output(), "f32 per pixel: AO in [0, 1] (gpu_types.h kAo*)",
                      std::to_string(f.settings.width) + " x " + std::to_string(f.settings.height));

  if (ao_->buildsLdms())
    passes_.push_back(ldmBuildPass(f, *ao_->ldm(), kLdmBuildPass, "ambient_occlusion.ldm", "ambient_occlusion"));
  FramePass pass;
  pass.name = kAmbientOcclusionPass;
  pass.reads = surfaceReads(surface);
  if (ao_->buildsLdms()) pass.reads.push_back("ambient_occlusion.ldm");
  if (f.resources.tlas(res::kTlas)) pass.reads.push_back(res::kTlas);
  if (as.computeBvh) pass.reads.push_back(res::kTraceBvh);
  pass.writes = {res::kAmbientOcclusion};
  pass.record = [this](VkCommandBuffer cmd, const PassFrame&) { ao_->recordAo(cmd); };
  pass.work = [pixels = double(f.settings.width) * f.settings.height](const nlohmann::json& a) {
    const nlohmann::json& ao = a.contains("ambient_occlusion") ? a["ambient_occlusion"] : nlohmann::json::object();
    const double directions = figureAt(ao, {"directions"});
    const double lit = pixels - figureAt(ao, {"pixels_sky"}) - figureAt(ao, {"pixels_without_normal"});
    const std::string method = ao.value("method", "");
    WorkItem item;
    if (method == "raytraced")
      item = derived("rays_ao", lit * directions, "one ray per direction per pixel with a surface");
    else if (method == "hbao")
      item = derived("bytes", lit * directions * figureAt(ao, {"steps"}) * 4,
                     "a 4 B depth texel per step per direction per pixel (most from cache)");
    else if (method == "gtao")
      item = derived("bytes", lit * directions * figureAt(ao, {"steps"}) * 2 * 4,
                     "a 4 B depth texel per step on each side of each slice per pixel (most from cache)");
    else if (method == "reference")
      item = derived("rays_ao", lit * figureAt(ao, {"samples"}), "one ray per sample per pixel with a surface");
    else
      item = derived("bytes", lit * directions * 8, "at least one 8 B list node read per direction per pixel");
    return std::vector<PassWork>{{kAmbientOcclusionPass, {item}}};
  };
  passes_.push_back(std::move(pass));
}

AoPass* aoPassOf(const Renderer& renderer) {
  const AoPart* p = renderer.part<AoPart>(ambientOcclusionEffect().name);
  return p ? &p->pass() : nullptr;
}

std::unique_ptr<FramePart> buildAmbientOcclusion(FrameBuilder& frame) { return std::make_unique<AoPart>(frame); }

}  // namespace hb
