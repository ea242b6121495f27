// The environment light in the frame: the LDM build ("environment_ldm_build", method ldm) and the
// environment-light pass ("environment_light": effects/ambient_occlusion/ao_pass.h with the
// scene's environment), publishing the light per pixel and declaring it a term shading reflects
// as albedo·(1 − metallic)·E (frame_pass.h ShadingTerm).
#pragma once
#include <memory>

#include "effects/ambient_occlusion/ao_pass.h"
#include "frame/frame_builder.h"
#include "frame/renderer.h"

namespace hb {

inline constexpr const char* kEnvironmentLdmBuildPass = "environment_ldm_build";
inline constexpr const char* kEnvironmentLightPass = "environment_light";
inline constexpr const char* kEnvironmentLightResource = "environment_light";  // vec4 per pixel

class EnvironmentLightPart : public FramePart {
 public:
  explicit EnvironmentLightPart(FrameBuilder& frame);
  AoPass& pass() const { return *pass_; }

 private:
  std::unique_ptr<AoPass> pass_;
};

// The frame's environment-light pass; null when the effect does not run.
AoPass* environmentPassOf(const Renderer& renderer);
std::unique_ptr<FramePart> buildEnvironmentLight(FrameBuilder& frame);

}  // namespace hb
