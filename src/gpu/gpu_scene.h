// The scene on the GPU: one vertex and one index buffer, and the draw list (instance × primitive)
// the raster passes walk.
#pragma once
#include <vector>

#include "scene/scene.h"
#include "gpu/vk_resources.h"

namespace hb {

struct DrawItem {
  glm::mat4 model;
  uint32_t firstIndex, indexCount, vertexOffset, material;
};

class GpuScene {
 public:
  GpuScene(const VulkanContext& ctx, const Scene& scene);
  const Scene& scene() const { return scene_; }
  const Buffer& vertices() const { return vertices_; }
  const Buffer& indices() const { return indices_; }
  const std::vector<DrawItem>& draws() const { return draws_; }

 private:
  const Scene& scene_;
  Buffer vertices_, indices_;
  std::vector<DrawItem> draws_;
};

}  // namespace hb
