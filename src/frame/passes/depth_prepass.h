// Pass 1, the depth prepass (thesis 4.1): the whole scene, depth only, reverse-Z (D32_SFLOAT
// cleared to 0, compare GREATER_OR_EQUAL), no fragment shader.
#pragma once
#include "gpu/gpu_scene.h"
#include "gpu/vk_pipeline.h"

namespace hb {

constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;

class DepthPrepass {
 public:
  DepthPrepass(const VulkanContext& ctx);
  ~DepthPrepass();
  // depth must be in DEPTH_ATTACHMENT_OPTIMAL; it is cleared to 0 and drawn.
  void record(VkCommandBuffer cmd, const GpuScene& scene, const glm::mat4& viewProj, const Image& depth) const;

 private:
  const VulkanContext& ctx_;
  Pipeline pipeline_;
};

}  // namespace hb
