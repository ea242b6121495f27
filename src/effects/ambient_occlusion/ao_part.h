// Ambient occlusion in the frame: the LDM build ("ldm_build", method ldm) and the AO pass
// ("ambient_occlusion", ao_pass.h) on the frame's surface, publishing the AO image for shading,
// which then composes direct + ambient·AO (the frame's ambient term is set here).
#pragma once
#include <memory>

#include "effects/ambient_occlusion/ao_pass.h"
#include "frame/frame_builder.h"
#include "frame/renderer.h"

namespace hb {

inline constexpr const char* kLdmBuildPass = "ldm_build";
inline constexpr const char* kAmbientOcclusionPass = "ambient_occlusion";

class AoPart : public FramePart {
 public:
  explicit AoPart(FrameBuilder& frame);
  AoPass& pass() const { return *ao_; }
  const TraceBvh* computeBvh() const { return ao_->settings().computeBvh; }  // backend=compute; null otherwise

 private:
  std::unique_ptr<AoPass> ao_;
};

// The frame's AO pass; null when the effect does not run.
AoPass* aoPassOf(const Renderer& renderer);
std::unique_ptr<FramePart> buildAmbientOcclusion(FrameBuilder& frame);

}  // namespace hb
