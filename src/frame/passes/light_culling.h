// Passes 2 and 3 (thesis 4.2): tile frustums (compute, once per camera/resolution/tile size) and
// light culling (compute, every frame, one workgroup per tile, gather approach). Outputs the light
// grid (offset, count, total per tile) and the tile lists, in one of three forms (light_lists):
//   tile:    the thesis's index list, fixed stride = capacity (32) per tile, capped;
//   bitmask: ceil(lights/32) mask words per tile, one bit per scene light, no cap (offset = the
//            tile's first word, count = total);
//   zbin:    the same masks over the lights sorted by view depth (Drobot 2017), followed in the list
//            buffer by kZBins log-depth bins, each the [first, last] sorted light that can reach it.
//            Sorting and binning run first in the same timed pass; later passes read the sorted
//            lights (lightsForLists) and map back through order().
// Before the tiles, every light is put in view space once (light_view.comp.glsl), so each tile
// transforms nothing and tests a light's 16-byte range sphere first, the rest only where it passes. Tile size, the AABB
// test, culling on/off and the list form are specialization constants: no dynamic branching on them.
#pragma once
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "config/config.h"
#include "gpu/gpu_timer.h"
#include "gpu/sync.h"
#include "gpu/vk_pipeline.h"
#include "gpu/vk_resources.h"

namespace hb {

// A view of the frame's settings (RenderSettings): a parameter the config has takes its one
// default from it (config.h paramDefaults); capacity and below are culling's own.
struct CullingSettings {
  uint32_t tileSize = paramDefaults().tileSize;
  bool lightCulling = paramDefaults().lightCulling;  // off: every tile gets every light
  bool aabb = paramDefaults().aabb;                  // Turanzkij's AABB test on top of the plane test
  uint32_t capacity = 32;                            // lights stored per tile (one 32-bit visibility mask)
  uint32_t depthSlices =
      paramDefaults().depthSlices;  // 0 off, 2..32: Harada's 2.5D slab test after the plane/AABB tests
  LightLists lists = paramDefaults().lightLists;
  uint32_t lightCount = 0;                  // sizes the masks (at most gpu::kMaxLights)
  float zbinNear = 0.1f, zbinFar = 100.0f;  // zbin: view distances the bins span (log-spaced)
};

// Buffers every later pass reads.
struct CullingOutputs {
  const Buffer* grid = nullptr;     // LightGridEntry per tile
  const Buffer* indices = nullptr;  // tile: uint per (tile, slot); masks: words per tile (+ z-bins)
  const Buffer* lights = nullptr;   // the lights the lists index (zbin: sorted by view depth)
  uint32_t tilesX = 0, tilesY = 0;
};

// Up to this many lights, each tile puts the lights in view space itself and runs the full test
// alone: at the thesis's 10 lights the sphere-first test (4b3dc94), which repeats part of the full
// one, and the light_view pass cost more than they save (issue #30, results/h100/bisect-30).
// Beyond it (many lights) light_view runs once per frame, and each tile reads range spheres first.
constexpr uint32_t kInlineViewMaxLights = 32;

class LightCulling {
 public:
  // frameConstants: UBO with gpu::FrameConstants; lights: SSBO of gpu::GpuLight; depth: the
  // prepass depth (sampled in DEPTH_READ_ONLY_OPTIMAL through `sampler`).
  LightCulling(const VulkanContext& ctx, const CullingSettings& settings, uint32_t width, uint32_t height,
               const Buffer& frameConstants, const Buffer& lights, const Image& depth, VkSampler sampler);
  ~LightCulling();

  // Computes the tile frustums; record once per camera/resolution/tile size.
  void recordFrustums(VkCommandBuffer cmd, Sync& sync) const;
  // Culls every frame, declaring each dispatch's accesses through `sync` (the frame's). Depth must
  // be readable by compute shaders (the pass declares it). With a timer, each dispatch of a
  // pass of several is timed as a sub-pass (subPasses()).
  void recordCulling(VkCommandBuffer cmd, Sync& sync, uint32_t lightCount, GpuTimer* timer = nullptr) const;
  // The timer entries recordCulling writes inside the pass's own: "light_culling.zbin_sort",
  // ".zbin_bins", ".light_view" and ".tiles", those of the dispatches this configuration runs;
  // none when it runs the tile test alone.
  std::vector<std::string> subPasses() const;
  // The bytes each of those dispatches moves at least (derived from sizes: what it reads and
  // writes once), and for the sort its compares, by sub-pass name.
  struct SubPassWork {
    std::string name;
    double bytes = 0, compares = 0;
  };
  std::vector<SubPassWork> subPassWork(uint32_t lightCount) const;

  CullingOutputs outputs() const {
    return {&grid_, &indices_, settings_.lists == LightLists::Zbin ? &sortedLights_ : &lights_, tilesX_, tilesY_};
  }
  // The list memory: grid, lists (and for zbin the bins, sorted lights, order and extents).
  uint64_t memoryBytes() const;
  const CullingSettings& settings() const { return settings_; }
  // FrameConstants.lists and .zbins for these lists (gpu_types.h).
  glm::uvec4 listConstants() const;
  glm::vec4 zbinConstants() const;
  uint32_t maskWords() const { return maskWords_; }  // bitmask, zbin: words per tile
  const Buffer& order() const { return order_; }     // zbin: sorted index -> scene light index

 private:
  // Binds `pipeline` with its descriptor set, pushes `push` (4 bytes) and dispatches.
  void dispatch(VkCommandBuffer cmd, const Pipeline& pipeline, uint32_t push, uint32_t groupsX,
                uint32_t groupsY = 1) const;
  const VulkanContext& ctx_;
  CullingSettings settings_;
  uint32_t tilesX_, tilesY_, maskWords_;
  double pixels_;
  bool inlineView_ = false;  // few lights: no light_view pass (kInlineViewMaxLights)
  const Buffer& lights_;
  Buffer frustums_, grid_, indices_, sortedLights_, order_, extents_, viewLights_, viewSpheres_;
  Pipeline frustumPipeline_, cullPipeline_, viewPipeline_, sortPipeline_, binPipeline_;
};

}  // namespace hb
