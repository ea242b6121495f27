#include "effects/indirect/indirect_part.h"

#include <string>

#include "effects/indirect/indirect_effect.h"
#include "frame/base_parts.h"
#include "frame/pass_work.h"

namespace hb {

IndirectPart::IndirectPart(FrameBuilder& f) {
  const SurfaceInputs surface = surfaceInputs(f);
  IndirectPassSettings is;
  is.indirect = indirectSettingsOf(f.value);
  is.worldPos = surface.worldPos;  // the surface as ambient occlusion takes it
  is.normals = surface.normals;
  is.rayQuery = f.settings.backend == RtBackend::RayQuery;  // the renderer resolved auto
  if (f.settings.backend == RtBackend::Compute) is.computeBvh = f.traceBvh;
  const IndirectInputs ii{surfaceBindings(f, surface), &f.resources.requireBuffer(res::kLights)};
  indirect_ = std::make_unique<IndirectPass>(f.ctx, f.gpuScene, f.scene, is, f.settings.width, f.settings.height, ii);
  f.resources.publish(res::kIndirectIrradiance, indirect_->irradiance(), "");

  const double pixels = double(f.settings.width) * f.settings.height;
  const double triangles = double(f.scene.triangleCount());
  // What each pass did, from the analysis frame's "indirect" record and the frame's sizes.
  auto workOf = [pixels, triangles](const std::string& name, const nlohmann::json& a) {
    const nlohmann::json& in = a.contains("indirect") ? a["indirect"] : nlohmann::json::object();
    const double slots = figureAt(in, {"split_photons", "slots"});
    std::vector<WorkItem> items;
    if (name == kIndirectLdmBuildPass)
      items = ldmBuildWork(in, triangles);
    else if (name == kPhotonTracePass && in.value("method", "") == "ldm")
      items = {derived("bytes", 8 * slots, "at least one 8 B list node read per photon slot")};
    else if (name == kPhotonTracePass)
      items = {derived("rays_random", slots, "one ray per photon slot")};
    else if (name == kPhotonSplatPass)
      items = {derived("triangles", 2 * slots, "one quad (two triangles) per photon slot"),
               derived("bytes", 16 * pixels + 64 * slots, "RGBA32F target written once, a 64 B photon read per slot")};
    else
      items = {derived("rays_random", pixels * figureAt(in, {"directions"}), "one gather ray per direction per pixel")};
    return std::vector<PassWork>{{name, items}};
  };
  auto add = [&](const char* name, std::vector<std::string> reads, std::vector<std::string> writes,
                 void (IndirectPass::*record)(VkCommandBuffer) const) {
    FramePass pass;
    pass.name = name;
    pass.reads = std::move(reads);
    pass.writes = std::move(writes);
    pass.record = [this, record](VkCommandBuffer cmd, const PassFrame&) { (indirect_.get()->*record)(cmd); };
    pass.work = [workOf, name = std::string(name)](const nlohmann::json& a) { return workOf(name, a); };
    passes_.push_back(std::move(pass));
  };
  std::vector<std::string> traceReads = surfaceReads(surface);
  traceReads.push_back(res::kTlas);
  traceReads.push_back(res::kLights);
  if (indirect_->buildsLdms()) {
    f.resources.publish("indirect.ldm", indirect_->ldm()->links(), "u64 or u32 list nodes", "counted per frame + 5 %");
    add(kIndirectLdmBuildPass, {res::kSceneVertices, res::kSceneIndices}, {"indirect.ldm"}, &IndirectPass::recordBuild);
    traceReads.push_back("indirect.ldm");
  }
  if (indirect_->method() == IndirectMethod::Reference) {
    add(kIndirectGatherPass, traceReads, {res::kIndirectIrradiance}, &IndirectPass::recordGather);
  } else {
    f.resources.publish("indirect.photons", indirect_->photonSlots(), "gpu::Photon per slot",
                        std::to_string(indirect_->slots()) + " slots (primaries x N)");
    add(kPhotonTracePass, traceReads, {"indirect.photons"}, &IndirectPass::recordTrace);
    add(kPhotonSplatPass, {"indirect.photons", res::kFrameConstants}, {res::kIndirectIrradiance},
        &IndirectPass::recordSplat);
  }
}

IndirectPass* indirectPassOf(const Renderer& renderer) {
  const IndirectPart* p = renderer.part<IndirectPart>(indirectEffect().name);
  return p ? &p->pass() : nullptr;
}

std::unique_ptr<FramePart> buildIndirect(FrameBuilder& frame) { return std::make_unique<IndirectPart>(frame); }

}  // namespace hb
