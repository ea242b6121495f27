#include "frame/passes/trace_bvh.h"

#include <algorithm>
#include <cstring>
#include <vector>

#include "frame/passes/primary_bvh.h"

namespace hb {

TraceBvhLayout layoutTraceBvh(const std::vector<glm::vec3>& vertices) {
  const PrimaryBvh tree = buildPrimaryBvh(vertices);
  TraceBvhLayout out;
  out.triangles.reserve(3 * tree.order.size());
  for (uint32_t id : tree.order) {
    float idBits;
    std::memcpy(&idBits, &id, sizeof id);
    out.triangles.emplace_back(vertices[3 * size_t(id)], idBits);
    for (size_t k = 1; k < 3; ++k) out.triangles.emplace_back(vertices[3 * size_t(id) + k], 1.0f);
  }
  out.nodes = tree.nodes;
  out.depth = tree.depth;
  out.stack = std::max(1u, tree.depth > 1 ? tree.depth - 1 : 1u);
  out.buildMs = tree.buildMs;
  return out;
}

uint32_t traceBvhTriangleId(const TraceBvhLayout& layout, size_t slot) {
  uint32_t id;
  std::memcpy(&id, &layout.triangles[3 * slot].w, sizeof id);
  return id;
}

TraceBvh buildTraceBvh(const VulkanContext& ctx, const Scene& scene) {
  TraceBvhLayout l = layoutTraceBvh(scene.worldTriangles());
  if (l.triangles.empty()) l.triangles.assign(3, glm::vec4(0.0f));  // no triangle: a leaf of nothing is never read
  TraceBvh b;
  b.nodes = uploadBuffer(ctx, l.nodes.data(), l.nodes.size() * sizeof(gpu::PrimaryBvhNode),
                         VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemClass::Geometry);
  b.triangles = uploadBuffer(ctx, l.triangles.data(), l.triangles.size() * sizeof(glm::vec4),
                             VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemClass::Geometry);
  b.nodeCount = uint32_t(l.nodes.size());
  b.depth = l.depth;
  b.stack = l.stack;
  b.bytes = uint64_t(l.nodes.size() * sizeof(gpu::PrimaryBvhNode) + l.triangles.size() * sizeof(glm::vec4));
  b.buildMs = l.buildMs;
  return b;
}

}  // namespace hb
