// Ambient occlusion (effects/ambient_occlusion/ao_effect.h; Aalund et al. 2015 Sect. 3.3): per pixel, from
// the same position and normal the shadow pass uses (shaders/surface.glsl.inc), the share of the
// ambient light that arrives, by one of five methods of one meaning (shaders/ambient_occlusion/ao_common.glsl.inc):
//   ldm        layered depth maps along the N directions (LdmBuild, then a compute trace);
//   raytraced  the same N directions through the ray tracer (ray query, or the ray-tracing
//              pipeline on devices without it);
//   reference  cosine-weighted stratified Monte Carlo through the ray tracer;
//   hbao       screen space, horizon-based, from the depth buffer (the paper's comparison);
//   gtao       screen space, ground-truth-based (XeGTAO's slices), from the depth buffer.
// The frame's method writes output(); an analysis frame can compute the other methods on the same
// surface (computeWith) to measure the frame's method against them.
#pragma once
#include <map>
#include <memory>
#include <vector>

#include "config/config.h"
#include "effects/ambient_occlusion/ao_effect.h"
#include "frame/frame_builder.h"
#include "frame/passes/ldm_build.h"
#include "gpu/descriptor_binder.h"
#include "gpu/gpu_timer.h"
#include "gpu/rt_pipeline.h"
#include "gpu/trace_bvh.h"
#include "gpu/vk_pipeline.h"
#include "gpu/vk_resources.h"
#include "scene/scene.h"

namespace hb {

// The frame's surface and ray tracer (frame_builder.h); tlas null: only ldm can run, and
// computeWith cannot.
using AoInputs = SurfaceBindings;

struct AoPassSettings {
  AoSettings ao;
  NormalCulling normals = NormalCulling::Improved;  // frame_builder.h SurfaceInputs
  WorldPosMethod worldPos = WorldPosMethod::Alg41;
  // The frame's ray tracer (null: none, only ldm, hbao and gtao run). backend=compute: raytraced and
  // reference trace through its BVH (compute_occluded.glsl.inc) instead of the TLAS; else through
  // the device's ray query where it has it, or the ray-tracing pipeline.
  const RayTracer* tracer = nullptr;
  const TraceBvh* computeBvh() const { return tracer && tracer->compute() ? tracer->bvh : nullptr; }
  // Environment light (effects/environment_light/env_effect.h): the same methods (ldm, raytraced,
  // reference) weighing each direction by this environment's radiance (ao_common.glsl.inc
  // RADIANCE); output() then holds 4 floats a pixel. Null: ambient occlusion.
  const Environment* environment = nullptr;
  // The name its errors and LDM build go by ("ambient_occlusion", "environment_light").
  const char* effect = "ambient_occlusion";
};

struct AoMemory {
  uint64_t ldmLinkBytes = 0, ldmMapBytes = 0, directionBytes = 0, outputBytes = 0, environmentBytes = 0;
  uint64_t total() const { return ldmLinkBytes + ldmMapBytes + directionBytes + outputBytes + environmentBytes; }
};

class AoPass {
 public:
  // Throws InputError when the settings cannot run here (directions, a method without a tracer).
  // Method ldm traces through the set ldmSource gives for its directions (the frame's, shared).
  AoPass(const VulkanContext& ctx, const Scene& scene, const AoPassSettings& settings, uint32_t width, uint32_t height,
         const AoInputs& inputs, const LdmSource& ldmSource);
  ~AoPass();

  // The AO computation ("ambient_occlusion"; the LDM build, ldm(), is its own pass: ldmBuildPass).
  // After it, output() holds one float per pixel (AO in [0, 1], gpu::kAoSky, gpu::kAoNoNormal), or
  // with an environment 4 (rgb, w = 1 or the status).
  void recordAo(VkCommandBuffer cmd) const;
  bool buildsLdms() const { return bool(ldm_); }

  const Buffer& output() const { return output_; }
  std::vector<float> readAo() const;
  // Analysis frames: the AO of `method` on the surface of the last frame (its own submission);
  // reference takes kAoReferenceSamples rays a pixel, whatever the frame's method uses.
  // Precondition: a tracer (inputs.tlas) for raytraced/reference.
  std::vector<float> computeWith(AoMethod method);
  bool canTrace() const { return tlas_ != VK_NULL_HANDLE; }
  uint32_t channels() const { return settings_.environment ? 4u : 1u; }
  const VulkanContext& context() const { return ctx_; }

  const AoPassSettings& settings() const { return settings_; }
  const LdmBuild* ldm() const { return ldm_; }
  AoMemory memory() const;
  uint32_t ldmNodeCapacity() const { return ldm_ ? ldm_->nodeCapacity() : 0; }

 private:
  struct Program;  // one method's pipeline
  const Program& program(AoMethod method);
  // scratch: into scratch_ with the reference's parameters (computeWith), else into output_.
  void recordProgram(VkCommandBuffer cmd, const Program& p, bool scratch) const;

  const VulkanContext& ctx_;
  AoPassSettings settings_;
  uint32_t width_, height_;
  VkAccelerationStructureKHR tlas_;
  const LdmBuild* ldm_ = nullptr;  // the frame's (frame_builder.h frameLdmSet), maybe shared
  Buffer directions_, params_, scratchParams_, output_, scratch_, placeholder_, environment_;
  // The pass's resources by name: over output_ and params_, and (with a tracer) over scratch_ and
  // scratchParams_; kept, since a method's program is built when first used.
  std::unique_ptr<DescriptorBinder> binder_, scratchBinder_;
  std::map<AoMethod, std::unique_ptr<Program>> programs_;
};

}  // namespace hb
