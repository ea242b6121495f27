// The scene's textures on the GPU: mipmapped images (sRGB for base colour, linear for
// metallic-roughness) for the bindless descriptor array, and the materials buffer.
#pragma once
#include <vector>

#include "gpu/vk_resources.h"
#include "scene/scene.h"

namespace hb {

class GpuTextures {
 public:
  // Always holds at least one texture (a 1x1 white one when the scene has none), so the
  // variable-length descriptor array is never empty.
  GpuTextures(const VulkanContext& ctx, const Scene& scene);
  ~GpuTextures();
  const std::vector<Image>& images() const { return images_; }
  VkSampler sampler() const { return sampler_; }
  const Buffer& materials() const { return materials_; }

 private:
  const VulkanContext& ctx_;
  std::vector<Image> images_;
  VkSampler sampler_ = VK_NULL_HANDLE;
  Buffer materials_;
};

}  // namespace hb
