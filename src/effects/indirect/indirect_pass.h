// Single-bounce indirect light (effects/indirect/indirect_effect.h; Aalund et al. 2015 Sect. 3.4, 4.2): per frame
//   ldm        the LDMs along the N directions ("indirect_ldm_build"), the photons traced
//              ("photon_trace": shaders/indirect/indirect_common.glsl.inc) and splatted ("photon_splat"):
//              splat=compute bins the photons into 16x16 tiles and gathers them a tile a group in
//              slot order (photon_splat_bin.comp.glsl, photon_splat.comp.glsl); splat=raster draws
//              a quad a photon with additive blending into the RGBA32F target
//              (photon_splat.{vert,frag}.glsl). Both sum the same terms in the same order;
//   raytraced  the same photons traced by the ray tracer, splatted the same way;
//   reference  the gathered single bounce per pixel ("indirect_gather").
// irradiance() then holds E_indirect (rgb, W/m²) per pixel, which the shading pass reflects as
// albedo·(1 − metallic)/π·E. Every photon has a fixed slot (primary · N + direction), written
// every frame, and either splat sums the slots in slot order: the result is deterministic. An analysis
// frame can compute the other methods on the same surface (computeWith).
#pragma once
#include <array>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "config/config.h"
#include "effects/indirect/indirect_effect.h"
#include "frame/frame_builder.h"
#include "frame/passes/ldm_build.h"
#include "gpu/gpu_textures.h"
#include "gpu/gpu_timer.h"
#include "gpu/rt_pipeline.h"
#include "gpu/sync.h"
#include "gpu/trace_bvh.h"
#include "gpu/vk_pipeline.h"
#include "gpu/vk_resources.h"
#include "scene/scene.h"

namespace hb {

// The frame's surface and ray tracer (frame_builder.h; the tracer is required: every method meets
// surfaces by ray) and the scene's lights.
struct IndirectInputs : SurfaceBindings {
  const Buffer* lights = nullptr;
};

struct IndirectPassSettings {
  IndirectSettings indirect;
  NormalCulling normals = NormalCulling::Improved;  // as AoPassSettings
  WorldPosMethod worldPos = WorldPosMethod::Alg41;
  // The frame's ray tracer (required): its backend, where the device has ray queries (else the
  // ray-tracing pipeline), and backend=compute's BVH instead of either.
  const RayTracer* tracer = nullptr;
  const TraceBvh* computeBvh() const { return tracer && tracer->compute() ? tracer->bvh : nullptr; }
};

struct IndirectMemory {
  uint64_t ldmBytes = 0, photonBytes = 0, faceBytes = 0, directionBytes = 0, targetBytes = 0, textureBytes = 0;
  uint64_t splatBytes = 0;  // splat=compute: the boxes, bins and list
  uint64_t total() const {
    return ldmBytes + photonBytes + faceBytes + directionBytes + targetBytes + textureBytes + splatBytes;
  }
};

// What became of the split photons of one trace (a readback of every slot) and their flux (W,
// the sum of the three channels).
struct PhotonTally {
  uint64_t slots = 0, stored = 0, hidden = 0, escaped = 0, grazing = 0, empty = 0;
  double fluxStored = 0, fluxHidden = 0, fluxEscaped = 0, fluxGrazing = 0;
  double fluxReflected() const { return fluxStored + fluxHidden + fluxEscaped + fluxGrazing; }
};
PhotonTally tallyPhotons(const std::vector<gpu::Photon>& photons);

class IndirectPass {
 public:
  // Throws InputError when the settings cannot run here (directions; a photon buffer over the
  // device's storage-buffer range; no ray tracer; splat=compute without compute subgroup ballots),
  // DeviceError when the device cannot blend RGBA32F. Method ldm traces through the set ldmSource
  // gives for its directions (the frame's, shared).
  IndirectPass(const VulkanContext& ctx, const GpuScene& gpuScene, const Scene& scene,
               const IndirectPassSettings& settings, uint32_t width, uint32_t height, const IndirectInputs& inputs,
               const LdmSource& ldmSource);
  ~IndirectPass();

  bool buildsLdms() const { return bool(ldm_); }
  // Each declares its steps' accesses to the photons and the target through `sync` (the frame's).
  void recordTrace(VkCommandBuffer cmd, Sync& sync) const;  // "photon_trace" (ldm, raytraced)
  // "photon_splat"; splat=compute times its steps inside it (splatSubPasses) where `timer` is given.
  // analysis (splat=compute): the gather counts its work (splatStats' tests and terms).
  void recordSplat(VkCommandBuffer cmd, Sync& sync, GpuTimer* timer = nullptr, bool analysis = false) const;
  std::vector<std::string> splatSubPasses() const;           // "photon_splat.boxes", ... (splat=compute)
  void recordGather(VkCommandBuffer cmd, Sync& sync) const;  // "indirect_gather" (reference)

  const IndirectPassSettings& settings() const { return settings_; }
  IndirectMethod method() const { return settings_.indirect.method; }
  const Image& irradiance() const { return frame_.irradiance; }  // RGBA32F, GENERAL layout
  const Buffer& photonSlots() const { return frame_.photons; }   // gpu::Photon per slot (not for reference)
  std::vector<float> readIrradiance() const;                     // rgba per pixel
  std::vector<gpu::Photon> readPhotons() const;                  // every slot (not for reference)
  // Analysis frames: the irradiance (rgba per pixel) of `method` on the surface of the last frame,
  // computed into a second target (its own submissions); photons, when given, receive its slots.
  std::vector<float> computeWith(IndirectMethod method, std::vector<gpu::Photon>* photons = nullptr);

  // Light leaving the emitters through their faces (W, the three channels summed): Σ I·Ω·spot
  // over every texel, in double (reference/photon_ref.h), before any range window.
  double emittedFlux() const { return emittedFlux_; }
  uint32_t primaries() const { return primaries_; }
  // Photon slots in all: bounce 1's P·N, then each further bounce's P·N·M_2···M_b
  // (indirect_common.glsl.inc bounceTrace), in that order.
  uint64_t slots() const { return bounceFirstSlot(settings_.indirect.bounces + 1); }
  uint64_t bounceSlots(uint32_t bounce) const;      // bounce >= 1
  uint64_t bounceFirstSlot(uint32_t bounce) const;  // where bounce's slots begin (bounces + 1: the end)
  uint32_t emitters() const { return emitters_; }
  // The landing test's LDM term, (√2/2)·s_ldm + 2·kShadowTMin (indirect_common.glsl.inc
  // landsVisible): how far off the surface an LDM-traced photon may land.
  double landingTolerance() const { return 0.70710678 * ldmPixel_ + 2.0 * gpu::kShadowTMin; }
  const LdmBuild* ldm() const { return ldm_; }
  IndirectMemory memory() const;
  // splat=compute, after a frame: the coarse bins' list entries (slot-bin pairs), the bins, and the
  // bins whose entries passed the list's capacity (gathered from every slot instead).
  struct SplatStats {
    uint64_t entries = 0, bins = 0, overCapacity = 0, capacity = 0;
    // The last analysis frame's gathers: pixel-photon coverage tests and the terms added, the first
    // bounce's (or every bounce's) run and the later bounces' run (later_bounce_stride > 1).
    uint64_t tests = 0, terms = 0, laterTests = 0, laterTerms = 0;
    bool counted = false;  // an analysis frame has run
  };
  std::optional<SplatStats> splatStats() const;
  // splat=compute: the last run's binning as the gather reads it (tests; photon_splat_bin.comp.glsl):
  // every slot's coarse box (x0 | y0 << 8 | x1 << 16 | y1 << 24), each bin's (start, entries, fits)
  // and the list's first `entries` of all bins; the run's slots [first, first + slots).
  struct SplatBins {
    std::vector<uint32_t> coarse, list;
    std::vector<std::array<uint32_t, 3>> bins;
    uint32_t binsX = 0, binsY = 0, first = 0, slots = 0, capacity = 0;
  };
  std::optional<SplatBins> readSplatBins() const;
  // splat=compute: what the driver compiled the count, fill and timed gathers into (registers,
  // shared memory, spills: gpu/vk_pipeline.h pipelineStatistics), by step; null where the device
  // does not say.
  nlohmann::json splatPipelineStatistics() const;
  // splat=compute: the bins of a row each count and fill group takes (photon_splat_bin.comp.glsl):
  // the widest of 8, 4, 2 that still leaves 512 groups for a run of `chunks` slot chunks over
  // binsX x binsY bins, else 1.
  static uint32_t splatRowBins(uint64_t chunks, uint32_t binsX, uint32_t binsY);
  // Tests: every run's row width from the next frame on (1, 2, 4 or 8), whatever the rule says.
  void forceSplatRowBins(uint32_t rowBins);
  // Tests: every word of the splat's list set to `value` now, so that an entry the next frame's
  // fill leaves unwritten shows (a fresh buffer may hold an earlier renderer's list).
  void fillSplatList(uint32_t value);

 private:
  struct Target {
    Buffer photons;
    Image irradiance;
    Image late;  // splat=compute: the later bounces at their receivers (later_bounce_stride > 1), else 1x1
    std::unique_ptr<DescriptorSets> sets;
  };
  struct Program;
  Target makeTarget(bool withPhotons);
  const Program& program(IndirectMethod method, uint32_t bounce = 1);
  // Every bounce's trace (programs created: program(method, b) for b = 1..bounces).
  void recordTraceInto(VkCommandBuffer cmd, Sync& sync, IndirectMethod method, const Target& t) const;
  void recordSplatInto(VkCommandBuffer cmd, Sync& sync, const Target& t, GpuTimer* timer, bool analysis = false) const;
  void recordGatherInto(VkCommandBuffer cmd, Sync& sync, const Program& p, const Target& t) const;
  void recordDispatch(VkCommandBuffer cmd, const Program& p, const Target& t, uint32_t count, bool pixels) const;

  const VulkanContext& ctx_;
  const GpuScene& gpuScene_;
  IndirectPassSettings settings_;
  bool rayQuery_ = false;  // the frame's backend is rayquery and the device has it (else the pipeline, or compute)
  IndirectInputs in_;
  uint32_t width_, height_;
  uint32_t primaries_ = 0, emitters_ = 0;
  double emittedFlux_ = 0, ldmPixel_ = 0;
  std::unique_ptr<GpuTextures> textures_;
  const LdmBuild* ldm_ = nullptr;  // the frame's (frame_builder.h frameLdmSet), maybe shared
  Buffer directions_, params_, faces_, draws_, triangleDraw_, idBase_, placeholder_;
  std::unique_ptr<ShaderProgram> shaders_;  // every shader a target's set serves, their bindings merged
  Target frame_, scratch_;
  Pipeline splat_;
  // splat=compute: the binning's buffers (in the targets' sets), its four steps and the gather.
  struct ComputeSplat;  // indirect_splat.h
  std::unique_ptr<ComputeSplat> computeSplat_;
  // splat=compute (indirect_splat.cpp): its constants and buffers, then (after the frame's target,
  // whose set they use) its pipelines; the latter does nothing without the splat.
  void setUpComputeSplat(uint32_t width, uint32_t height, const VkPhysicalDeviceProperties& props);
  void createComputeSplatPipelines();
  void recordComputeSplat(VkCommandBuffer cmd, Sync& sync, const Target& t, GpuTimer* timer, bool analysis) const;
  mutable bool splatCounted_ = false;
  std::map<std::pair<IndirectMethod, uint32_t>, std::unique_ptr<Program>> programs_;  // (method, bounce)
};

}  // namespace hb
