#include "effects/indirect/indirect_part.h"

#include <string>

#include "effects/indirect/indirect_effect.h"
#include "frame/base_parts.h"

namespace hb {

IndirectPart::IndirectPart(FrameBuilder& f) {
  const SurfaceInputs surface = surfaceInputs(f);
  IndirectPassSettings is;
  is.indirect = indirectSettingsOf(f.value);
  is.worldPos = surface.worldPos;  // the surface as ambient occlusion takes it
  is.normals = surface.normals;
  is.rayQuery = f.settings.backend != RtBackend::Pipeline && f.ctx.info().rayQuery;  // backend=pipeline: every ray pass
  const IndirectInputs ii{surfaceBindings(f, surface), &f.resources.requireBuffer(res::kLights)};
  indirect_ = std::make_unique<IndirectPass>(f.ctx, f.gpuScene, f.scene, is, f.settings.width, f.settings.height, ii);
  f.resources.publish(res::kIndirectIrradiance, indirect_->irradiance(), "");

  auto add = [&](const char* name, std::vector<std::string> reads, std::vector<std::string> writes,
                 void (IndirectPass::*record)(VkCommandBuffer) const) {
    FramePass pass;
    pass.name = name;
    pass.reads = std::move(reads);
    pass.writes = std::move(writes);
    pass.record = [this, record](VkCommandBuffer cmd, const PassFrame&) { (indirect_.get()->*record)(cmd); };
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
