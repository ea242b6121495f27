// Pass 4 (thesis 4.3): ray-traced hard shadows with two backends of one meaning —
// `rayquery` (compute shader, tile depth in group shared memory, VK_KHR_ray_query) and `pipeline`
// (ray generation + miss shader, VK_KHR_ray_tracing_pipeline). Writes the r32ui visibility mask
// (bit i = light i of the pixel's tile is visible). Analysis frames use a second pipeline that
// also writes the per-pixel ray accounting, the reconstructed normals and the world positions;
// timed frames carry none of it (specialization constants, not branches).
#pragma once
#include <memory>

#include "gpu/vk_pipeline.h"
#include "gpu/vk_resources.h"

namespace hb {

enum class ShadowBackend { RayQuery, Pipeline };
const char* toString(ShadowBackend);

struct ShadowSettings {
  ShadowBackend backend = ShadowBackend::RayQuery;
  uint32_t tileSize = 16;
  uint32_t normals = 0;   // gpu::kNormalsOff / Naive / Improved / Geometric (needs hit ids)
  uint32_t worldPos = 0;  // gpu::kWorldPosAlg41 / Matrix / Hit (needs hit ids)
  bool rangeTest = false;
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

  const Image& visibility() const { return visibility_; }
  const Image& accounting() const { return accounting_; }
  const Image& normals() const { return normals_; }
  const Image& positions() const { return positions_; }
  const Image& traced() const { return traced_; }  // analysis: bit i = the ray to tile light i was traced
  const ShadowSettings& settings() const { return settings_; }

 private:
  struct Variant;  // one pipeline (timed or analysis) of the chosen backend
  const VulkanContext& ctx_;
  ShadowSettings settings_;
  uint32_t width_, height_;
  Image visibility_, accounting_, normals_, positions_, traced_;
  DescriptorSets sets_;
  std::unique_ptr<Variant> timed_, analysis_;
};

}  // namespace hb
