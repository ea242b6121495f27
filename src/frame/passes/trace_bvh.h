// Our BVH for tracing rays in compute (backend=compute, shaders/compute_occluded.glsl.inc): primary
// visibility's binary SAH tree (primary_bvh.h) uploaded with its triangles copied in leaf order
// (3 vec4 each; the first vertex's w holds the triangle's draw-order id as bits, for closest hits),
// so that a leaf's triangles are contiguous. Built once per renderer and shared by every pass that
// traces (the frame resource "trace_bvh", renderer.cpp).
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "gpu/vk_resources.h"
#include "scene/scene.h"
#include "shared/gpu_types.h"

namespace hb {

// What is uploaded, built on the CPU (tested without a device: trace_bvh_test.cpp).
struct TraceBvhLayout {
  std::vector<gpu::PrimaryBvhNode> nodes;
  std::vector<glm::vec4> triangles;  // 3 per triangle in leaf order; [3i].w = the id's bits
  uint32_t depth = 0;
  uint32_t stack = 1;  // the traversal stack's entries: depth − 1 (a node is pushed once per level)
  double buildMs = 0.0;
};
// `vertices`: 3 per triangle, world space (Scene::worldTriangles()).
TraceBvhLayout layoutTraceBvh(const std::vector<glm::vec3>& vertices);
// The id a layout's triangle slot carries (the bits of its first vertex's w).
uint32_t traceBvhTriangleId(const TraceBvhLayout& layout, size_t slot);

struct TraceBvh {
  Buffer nodes;      // gpu::PrimaryBvhNode
  Buffer triangles;  // 3 vec4 per triangle, in leaf order
  uint32_t nodeCount = 0, depth = 0;
  uint32_t stack = 1;
  uint64_t bytes = 0;
  double buildMs = 0.0;  // the CPU build; the upload is not counted
};

TraceBvh buildTraceBvh(const VulkanContext& ctx, const Scene& scene);

// Whether a workgroup of `threads` keeps its traversal stacks in shared memory (compute_occluded's
// HB_BVH_SHARED_ID): at most 16 KiB of them, so that the pass's own shared memory and several
// workgroups an SM still fit (the atrium's 26 entries: 6.6 KiB at 64 threads, 26.6 KiB at 256,
// 106 KiB at 1024, which lost the device on the H200). Otherwise the thread's local memory.
inline bool traceStackShared(const TraceBvh& bvh, uint32_t threads) {
  return uint64_t(bvh.stack) * threads * sizeof(uint32_t) <= 16384;
}

}  // namespace hb
