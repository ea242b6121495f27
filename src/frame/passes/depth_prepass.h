// Pass 1, the depth prepass (thesis 4.1): the whole scene, depth only, reverse-Z (D32_SFLOAT
// cleared to 0, compare GREATER_OR_EQUAL), no fragment shader.
#pragma once
#include "gpu/gpu_scene.h"
#include "gpu/vk_pipeline.h"

namespace hb {

constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;
// The frame's depth where no pass draws against it (a compute primary, visbuffer shading): a colour
// image, which the primary's resolve writes as a storage image instead of copying a buffer into a
// D32 one. The same values; passes sample it as they sample the D32 image.
constexpr VkFormat kComputeDepthFormat = VK_FORMAT_R32_SFLOAT;

// The layout the frame's passes sample its depth image in: a D32 image read-only, the colour one in
// GENERAL (where the resolve wrote it: no transition).
inline VkImageLayout depthReadLayout(const Image& depth) {
  return depth.aspect() & VK_IMAGE_ASPECT_DEPTH_BIT ? VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL : VK_IMAGE_LAYOUT_GENERAL;
}

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
