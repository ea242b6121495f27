// Pass 4 (thesis 4.3): ray-traced hard shadows with two backends of one meaning —
// `rayquery` (compute shader, tile depth in group shared memory, VK_KHR_ray_query) and `pipeline`
// (ray generation + miss shader, VK_KHR_ray_tracing_pipeline). Writes the visibility words
// (shadows_common.glsl.inc: bit k = the k-th light of the pixel's list walk is visible; as many
// words per pixel as the lists need, so any number of lights). Analysis frames use a second pipeline that
// also writes the per-pixel ray accounting, the reconstructed normals and the world positions;
// timed frames carry none of it (specialization constants, not branches).
#pragma once
#include <memory>

#include "config/config.h"
#include "gpu/vk_pipeline.h"
#include "gpu/vk_resources.h"

namespace hb {

struct ShadowSettings {
  // The frame's ray tracer (frame/ray_backend.h RayTracer), never Auto; compute: our BVH
  // (trace_bvh.h) traversed in a compute shader (compute_occluded.glsl.inc).
  RtBackend backend = RtBackend::RayQuery;
  // A parameter the config has takes its one default from it (config.h paramDefaults).
  uint32_t tileSize = paramDefaults().tileSize;
  NormalCulling normals = paramDefaults().normalCulling;  // geometric needs hit ids
  WorldPosMethod worldPos = paramDefaults().worldPos;     // hit needs hit ids
  bool rangeTest = paramDefaults().rangeTest;
  uint32_t listMode = 0;            // gpu::kList*
  uint32_t visibilityWords = 1;     // per pixel: 1 for tile lists, ceil(lights/32) for the masks
  uint32_t bvhStack = 32;           // backend compute: the traversal stack's entries (the tree's depth − 1)
  bool bvhStackShared = true;       // backend compute: the stacks in shared memory (trace_bvh.h traceStackShared)
  bool raybenchStackShared = true;  // the same for raybench's 64-thread workgroups
  uint32_t bvhWidth = paramDefaults().bvhWidth;  // backend compute: our BVH's children a node
};

// Inputs shared with the other passes.
struct ShadowInputs {
  const Buffer* frameConstants;
  const Buffer* lights;
  const Buffer* grid;
  const Buffer* indices;
  const Image* depth;  // DEPTH_READ_ONLY_OPTIMAL
  VkSampler sampler;
  VkAccelerationStructureKHR tlas;
  // backend compute: our BVH's nodes (gpu::PrimaryBvhNode) and its triangles in leaf order (3 vec4).
  const Buffer* bvhNodes = nullptr;
  const Buffer* bvhTriangles = nullptr;
  // 3D rasterization's visibility buffer, ray constants and world triangles (nullptr after the
  // hardware prepass): what world_pos=hit and normal_culling=geometric read.
  const Buffer* hitIds = nullptr;
  const Buffer* hitRays = nullptr;
  const Buffer* hitTriangles = nullptr;
};

class ShadowPass {
 public:
  // Precondition: the device supports the chosen backend.
  ShadowPass(const VulkanContext& ctx, const ShadowSettings& settings, uint32_t width, uint32_t height,
             const ShadowInputs& inputs);
  ~ShadowPass();

  // Images are in GENERAL layout after construction.
  void record(VkCommandBuffer cmd, bool analysis) const;

  // Word-major: word j of pixel i at j·pixels + i; zbin: then a plane of pixel bin ranges.
  const Buffer& visibility() const { return visibility_; }
  const Image& accounting() const { return accounting_; }  // rgba32ui (gpu_types.h kAccount*)
  const Image& normals() const { return normals_; }
  const Image& positions() const { return positions_; }
  const Buffer& traced() const { return traced_; }  // analysis: as visibility, bit k = the ray was traced
  const ShadowSettings& settings() const { return settings_; }

 private:
  struct Variant;  // one pipeline (timed or analysis) of the chosen backend
  const VulkanContext& ctx_;
  ShadowSettings settings_;
  uint32_t width_, height_;
  Buffer visibility_, traced_;
  Image accounting_, normals_, positions_;
  std::unique_ptr<Variant> timed_, analysis_;
};

}  // namespace hb
