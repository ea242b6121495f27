// Ambient occlusion in the frame: the LDM build ("ldm_build", method ldm) and the AO pass
// ("ambient_occlusion", ao_pass.h) on the frame's surface, publishing the AO image and declaring
// the ambient term it lets through, albedo·(1 − metallic)·L_ambient·AO, for shading to add
// (frame_pass.h ShadingTerm; the frame's ambient term is set here).
#pragma once
#include <memory>

#include "effects/ambient_occlusion/ao_pass.h"
#include "frame/frame_builder.h"
#include "frame/renderer.h"

namespace hb {

inline constexpr const char* kLdmBuildPass = "ldm_build";
inline constexpr const char* kAmbientOcclusionPass = "ambient_occlusion";
inline constexpr const char* kAmbientOcclusionResource = "ambient_occlusion";  // float per pixel

class AoPart : public FramePart {
 public:
  explicit AoPart(FrameBuilder& frame);
  AoPass& pass() const { return *ao_; }
  const TraceBvh* computeBvh() const { return ao_->settings().computeBvh(); }  // backend=compute; null otherwise

 private:
  std::unique_ptr<AoPass> ao_;
};

// The frame's passes of an AoPass, for ambient occlusion and the environment light alike: its LDM
// build (where its method builds maps) and its own pass, which reads the frame's surface, the maps
// and the ray tracer it uses and writes `output`; its work is counted from report[effect] (the
// analysis frame's pixels, directions and samples).
struct AoPassNames {
  const char* effect;       // its key in the results: "ambient_occlusion", "environment_light"
  const char* buildPass;    // "ldm_build", "environment_ldm_build"
  const char* ldmResource;  // "ambient_occlusion.ldm", ...
  const char* pass;         // "ambient_occlusion", "environment_light"
  const char* output;       // the frame resource it writes
};
// `ldm`: the set the pass traces through (method ldm); where an earlier effect built it, the build
// pass is listed in `skipped` instead.
std::vector<FramePass> aoFramePasses(FrameBuilder& f, AoPass& pass, const SurfaceInputs& surface,
                                     const AoPassNames& names, const FrameLdmSet& ldm,
                                     std::vector<std::pair<std::string, std::string>>& skipped);
// An AoPass of these settings on the frame's surface; its LDM set (method ldm) is the frame's for
// its key (frameLdmSet), returned in `ldm`.
std::unique_ptr<AoPass> makeFrameAoPass(FrameBuilder& f, const AoPassSettings& settings, const AoInputs& inputs,
                                        const AoPassNames& names, FrameLdmSet& ldm);

// What an AoPass's report says of it whatever it computes (ao_report.cpp): pixels_sky and
// pixels_without_normal counted from its output `values` (their status channel), the tracer of its
// ray-traced methods, memory_bytes and its LDM lists.
void addAoPassFacts(nlohmann::json& report, const AoPass& pass, const std::vector<float>& values);

// The frame's AO pass; null when the effect does not run.
AoPass* aoPassOf(const Renderer& renderer);
std::unique_ptr<FramePart> buildAmbientOcclusion(FrameBuilder& frame);

}  // namespace hb
