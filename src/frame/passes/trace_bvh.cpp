#include "frame/passes/trace_bvh.h"

#include <algorithm>
#include <vector>

#include <glm/glm.hpp>

#include "frame/passes/primary_bvh.h"

namespace hb {

TraceBvh buildTraceBvh(const VulkanContext& ctx, const Scene& scene) {
  const std::vector<glm::vec3> world = scene.worldTriangles();
  const PrimaryBvh tree = buildPrimaryBvh(world);
  std::vector<glm::vec4> ordered;
  ordered.reserve(3 * tree.order.size());
  for (uint32_t id : tree.order)
    for (size_t k = 0; k < 3; ++k) ordered.emplace_back(world[3 * size_t(id) + k], 1.0f);
  if (ordered.empty()) ordered.assign(3, glm::vec4(0.0f));  // no triangle: a leaf of nothing is never read
  TraceBvh b;
  b.nodes = uploadBuffer(ctx, tree.nodes.data(), tree.nodes.size() * sizeof(gpu::PrimaryBvhNode),
                         VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemClass::Geometry);
  b.triangles = uploadBuffer(ctx, ordered.data(), ordered.size() * sizeof(glm::vec4),
                             VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemClass::Geometry);
  b.nodeCount = uint32_t(tree.nodes.size());
  b.depth = tree.depth;
  b.stack = std::max(1u, tree.depth > 1 ? tree.depth - 1 : 1u);
  b.bytes = uint64_t(tree.nodes.size() * sizeof(gpu::PrimaryBvhNode) + ordered.size() * sizeof(glm::vec4));
  b.buildMs = tree.buildMs;
  return b;
}

}  // namespace hb
