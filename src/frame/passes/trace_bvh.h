// Our BVH for tracing rays in compute (backend=compute, shaders/compute_occluded.glsl.inc): primary
// visibility's binary SAH tree (primary_bvh.h) uploaded with its triangles copied in leaf order
// (3 vec4 each), so that a leaf's triangles are contiguous. Built once per pass creation.
#pragma once
#include <cstdint>

#include "gpu/vk_resources.h"
#include "scene/scene.h"

namespace hb {

struct TraceBvh {
  Buffer nodes;      // gpu::PrimaryBvhNode
  Buffer triangles;  // 3 vec4 per triangle, in leaf order
  uint32_t nodeCount = 0, depth = 0;
  uint32_t stack = 1;  // the traversal stack's entries: depth − 1 (a node is pushed once per level)
  uint64_t bytes = 0;
  double buildMs = 0.0;
};

TraceBvh buildTraceBvh(const VulkanContext& ctx, const Scene& scene);

}  // namespace hb
