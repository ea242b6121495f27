// Passes 2 and 3 (thesis 4.2): tile frustums (compute, once per camera/resolution/tile size) and
// light culling (compute, every frame, one workgroup per tile, gather approach). Outputs the light
// grid (offset, count, total per tile) and the light index list (fixed stride = capacity per
// tile). Tile size, the AABB test and culling on/off are specialization constants: no dynamic
// branching on them.
#pragma once
#include "gpu/vk_pipeline.h"
#include "gpu/vk_resources.h"

namespace hb {

struct CullingSettings {
  uint32_t tileSize = 16;    // 8, 16 or 32
  bool lightCulling = true;  // off: every tile gets every light
  bool aabb = false;         // Turanzkij's AABB test on top of the plane test
  uint32_t capacity = 32;    // lights stored per tile (one 32-bit visibility mask)
  uint32_t depthSlices = 0;  // 0 off, 2..32: Harada's 2.5D slab test after the plane/AABB tests
};

// Buffers every later pass reads.
struct CullingOutputs {
  const Buffer* grid = nullptr;     // LightGridEntry per tile
  const Buffer* indices = nullptr;  // uint per (tile, slot)
  uint32_t tilesX = 0, tilesY = 0;
};

class LightCulling {
 public:
  // frameConstants: UBO with gpu::FrameConstants; lights: SSBO of gpu::GpuLight; depth: the
  // prepass depth (sampled in DEPTH_READ_ONLY_OPTIMAL through `sampler`).
  LightCulling(const VulkanContext& ctx, const CullingSettings& settings, uint32_t width, uint32_t height,
               const Buffer& frameConstants, const Buffer& lights, const Image& depth, VkSampler sampler);
  ~LightCulling();

  // Computes the tile frustums; record once per camera/resolution/tile size.
  void recordFrustums(VkCommandBuffer cmd) const;
  // Culls every frame. Depth must be readable by compute shaders.
  void recordCulling(VkCommandBuffer cmd, uint32_t lightCount) const;

  CullingOutputs outputs() const { return {&grid_, &indices_, tilesX_, tilesY_}; }
  uint64_t memoryBytes() const { return grid_.size() + indices_.size(); }
  const CullingSettings& settings() const { return settings_; }

 private:
  const VulkanContext& ctx_;
  CullingSettings settings_;
  uint32_t tilesX_, tilesY_;
  Buffer frustums_, grid_, indices_;
  DescriptorSets sets_;
  Pipeline frustumPipeline_, cullPipeline_;
};

}  // namespace hb
