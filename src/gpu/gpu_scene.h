// The scene on the GPU: one vertex and one index buffer, and the draw list (instance × primitive)
// the raster passes walk.
#pragma once
#include <vector>

#include "gpu/vk_resources.h"
#include "scene/scene.h"
#include "shared/gpu_types.h"

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

// What a pass that meets triangles by id needs to shade them (the visibility-buffer shading, the
// indirect light's photon hits): per draw item its matrices, material and first triangle, and per
// triangle (Scene::worldTriangles() order, the draw-order id) its draw item.
struct DrawTables {
  std::vector<gpu::GpuDraw> draws;
  std::vector<uint32_t> triangleDraw;
};
DrawTables drawTables(const GpuScene& scene);

// The draw-order triangle id of a ray hit (primary_raycast.glsl.inc): entry i < instances is the
// start of instance i's geometries; then per geometry (a primitive with a BLAS geometry, as
// accel.cpp builds them) the id of its first triangle, in Scene::worldTriangles() order.
std::vector<uint32_t> triangleIdBase(const Scene& scene);

}  // namespace hb
