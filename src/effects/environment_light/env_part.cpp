#include "effects/environment_light/env_part.h"

#include <string>

#include "base/errors.h"
#include "effects/environment_light/env_effect.h"
#include "frame/base_parts.h"
#include "frame/pass_work.h"

namespace hb {

EnvironmentLightPart::EnvironmentLightPart(FrameBuilder& f) {
  HB_ASSERT(f.scene.environment);
  const SurfaceInputs surface = surfaceInputs(f);
  AoPassSettings ps;
  ps.ao = environmentSettingsOf(f.value);
  ps.worldPos = surface.worldPos;
  ps.normals = surface.normals;
  ps.environment = &*f.scene.environment;
  ps.effect = environmentLightEffect().name;
  const AoInputs in = surfaceBindings(f, surface);
  if (f.settings.backend == RtBackend::Compute && in.tlas) ps.computeBvh = f.traceBvh;  // traces through our BVH
  pass_ = std::make_unique<AoPass>(f.ctx, f.gpuScene, f.scene, ps, f.settings.width, f.settings.height, in);
  f.resources.publish(res::kEnvironmentLight, pass_->output(),
                      "vec4 per pixel: (1/pi) integral of L V cos (rgb), w = 1 or kAoSky / kAoNoNormal",
                      std::to_string(f.settings.width) + " x " + std::to_string(f.settings.height));

  if (pass_->buildsLdms())
    passes_.push_back(ldmBuildPass(f, *pass_->ldm(), kEnvironmentLdmBuildPass, "environment_light.ldm",
                                   environmentLightEffect().name));
  FramePass pass;
  pass.name = kEnvironmentLightPass;
  pass.reads = surfaceReads(surface);
  if (pass_->buildsLdms()) pass.reads.push_back("environment_light.ldm");
  if (f.resources.tlas(res::kTlas)) pass.reads.push_back(res::kTlas);
  if (ps.computeBvh) pass.reads.push_back(res::kTraceBvh);
  pass.writes = {res::kEnvironmentLight};
  pass.record = [this](VkCommandBuffer cmd, const PassFrame&) { pass_->recordAo(cmd); };
  pass.work = [pixels = double(f.settings.width) * f.settings.height](const nlohmann::json& a) {
    const nlohmann::json& e = a.contains("environment_light") ? a["environment_light"] : nlohmann::json::object();
    const double directions = figureAt(e, {"directions"});
    const double lit = pixels - figureAt(e, {"pixels_sky"}) - figureAt(e, {"pixels_without_normal"});
    const std::string method = e.value("method", "");
    WorkItem item;
    if (method == "raytraced")
      item = derived("rays_ao", lit * directions, "one ray per direction per pixel with a surface");
    else if (method == "reference")
      item = derived("rays_ao", lit * figureAt(e, {"samples"}), "one ray per sample per pixel with a surface");
    else
      item = derived("bytes", lit * directions * 8, "at least one 8 B list node read per direction per pixel");
    return std::vector<PassWork>{{kEnvironmentLightPass, {item}}};
  };
  passes_.push_back(std::move(pass));
}

AoPass* environmentPassOf(const Renderer& renderer) {
  const EnvironmentLightPart* p = renderer.part<EnvironmentLightPart>(environmentLightEffect().name);
  return p ? &p->pass() : nullptr;
}

std::unique_ptr<FramePart> buildEnvironmentLight(FrameBuilder& frame) {
  return std::make_unique<EnvironmentLightPart>(frame);
}

}  // namespace hb
