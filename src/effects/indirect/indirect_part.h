// Indirect light in the frame: per method its passes ("indirect_ldm_build", "photon_trace",
// "photon_splat" or "indirect_gather", indirect_pass.h) on the frame's surface, publishing the
// irradiance and declaring it a term shading reflects as albedo·(1 − metallic)/π·E (frame_pass.h
// ShadingTerm).
#pragma once
#include <memory>

#include "effects/indirect/indirect_pass.h"
#include "frame/frame_builder.h"
#include "frame/renderer.h"

namespace hb {

inline constexpr const char* kIndirectLdmBuildPass = "indirect_ldm_build";
inline constexpr const char* kPhotonTracePass = "photon_trace";
inline constexpr const char* kPhotonSplatPass = "photon_splat";
inline constexpr const char* kIndirectGatherPass = "indirect_gather";
inline constexpr const char* kIndirectIrradianceResource = "indirect.irradiance";  // RGBA32F, W/m²

class IndirectPart : public FramePart {
 public:
  explicit IndirectPart(FrameBuilder& frame);
  IndirectPass& pass() const { return *indirect_; }

 private:
  std::unique_ptr<IndirectPass> indirect_;
};

// The frame's indirect-light pass; null when the effect does not run.
IndirectPass* indirectPassOf(const Renderer& renderer);
std::unique_ptr<FramePart> buildIndirect(FrameBuilder& frame);

}  // namespace hb
