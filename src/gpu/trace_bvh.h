// Our BVH for tracing rays in compute (backend=compute, shaders/compute_occluded.glsl.inc): primary
// visibility's binary SAH tree (primary_bvh.h), built with kTraceBvhBuild, uploaded with its triangles copied in leaf
// order (3 vec4 each; the first vertex's w holds the triangle's draw-order id as bits, for closest hits), so that a
// leaf's triangles are contiguous. Built once per renderer and shared by every pass that traces (the frame resource
// "trace_bvh", renderer.cpp).
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "gpu/primary_bvh.h"
#include "gpu/vk_resources.h"
#include "scene/scene.h"
#include "shared/gpu_types.h"

namespace hb {

// bvh_width=4 or 8: the binary tree collapsed into nodes of up to W children, the collapse of least
// SAH cost (trace_bvh.cpp SahCollapse: which binary nodes become wide nodes and which subtrees of up
// to 8 triangles become leaves), in groups of 4 children of 8 vec4 = 128 B: the children's lo.x, lo.y, lo.z,
// hi.x, hi.y, hi.z (one vec4 each, child k of the group in component k), their codes (vec4 of uint
// bits), and one unused; a node is W / 4 groups (width 4: 128 B, width 8: 256 B). A code is a wide
// node's index, or a leaf: kWideLeaf | (count − 1) << 28 | first (entries of the triangle order), or
// kWideEmpty for no child.
// The tracer's SAH: 64 bins on each of the three axes, where primary visibility's tree bins 12 on
// the centroids' widest. On the H200 the 4-wide tree traced the atrium's exported camera, AO and
// shadow rays faster with it, and the frame's own rays a little faster. The count was chosen by
// those measurements on that one scene; the full sweep was slower on the exported sets and faster on
// the frame's own rays (results/h200/tracer-51/tree, docs/rays.md). Then up to 40 rounds of
// reinsertion (bvh_reinsert.h; on the atrium it stops after fewer, once a round gains < 0.01 %):
// every backend traced every ray set faster through it on the H200, no frame pass slower
// (results/h200/tracer-51/reinsert).
inline constexpr BvhBuildOptions kTraceBvhBuild{64, true, 40};

inline constexpr uint32_t kWideLeaf = 0x80000000u;
inline constexpr uint32_t kWideEmpty = 0xFFFFFFFFu;
inline constexpr uint32_t kWideGroupVec4s = 8;  // a group of 4 children
inline constexpr uint32_t wideNodeVec4s(uint32_t width) { return 2 * width; }

// What is uploaded, built on the CPU (tested without a device: trace_bvh_test.cpp).
struct TraceBvhLayout {
  uint32_t width = 2;
  std::vector<gpu::PrimaryBvhNode> nodes;  // the binary tree (kept for widths 4, 8: a wide leaf is one of its subtrees)
  std::vector<glm::vec4> wide;             // width 4, 8: wideNodeVec4s(width) per node, the root first
  std::vector<glm::vec4> triangles;        // 3 per triangle in leaf order; [3i].w = the id's bits
  uint32_t depth = 0;                      // in nodes of the width's tree
  // The traversal stack's entries: binary depth − 1 (a node is pushed once per level), width W
  // (W − 1) · depth (up to W − 1 children pushed a level).
  uint32_t stack = 1;
  double buildMs = 0.0;
  uint64_t nodeBytes() const {
    return width != 2 ? wide.size() * sizeof(glm::vec4) : nodes.size() * sizeof(gpu::PrimaryBvhNode);
  }
};
// Child k of wide node `node` (width 4 or 8): its code and its box.
struct WideChild {
  uint32_t code = kWideEmpty;
  glm::vec3 lo{0.0f}, hi{0.0f};
};
WideChild wideChild(const std::vector<glm::vec4>& wide, uint32_t width, uint32_t node, uint32_t k);

// `vertices`: 3 per triangle, world space (Scene::worldTriangles()); width 2, 4 or 8.
TraceBvhLayout layoutTraceBvh(const std::vector<glm::vec3>& vertices, uint32_t width = 2,
                              const BvhBuildOptions& build = kTraceBvhBuild);
// The id a layout's triangle slot carries (the bits of its first vertex's w).
uint32_t traceBvhTriangleId(const TraceBvhLayout& layout, size_t slot);

struct TraceBvh {
  Buffer nodes;      // gpu::PrimaryBvhNode (width 2) or wideNodeVec4s(width) vec4 a node (4, 8)
  Buffer triangles;  // 3 vec4 per triangle, in leaf order
  uint32_t width = 2;
  uint32_t nodeCount = 0, depth = 0;
  uint32_t stack = 1;
  uint64_t bytes = 0;
  double buildMs = 0.0;  // the CPU build; the upload is not counted
};

TraceBvh buildTraceBvh(const VulkanContext& ctx, const Scene& scene, uint32_t width = 2);
// buildTraceBvh's calls since the process started, for tests that count a frame's builds.
uint64_t traceBvhBuildCount();

// Whether a workgroup of `threads` keeps its traversal stacks in shared memory (compute_occluded's
// second specialization constant): at most 8 KiB of them, else the thread's local memory. An entry
// is 4 B (the code), 8 B where the shader traces closest hits (HB_BVH_CLOSEST: the entry distance
// too). Measured on the H200 (results/h200/compute-backend-33/bvh-width): the atrium's binary tree,
// 26 entries, any hit at 64 threads: 6.6 KiB, shared, 4.5 G rays/s; with distances, 13.3 KiB: its
// closest hits ran 1.30 ms a 1080p frame in shared memory against 0.79 ms in local memory, and the
// 4-wide tree's any-hit stack (45 entries, 11.5 KiB) 1.33 ms in shared against 1.06 ms in local:
// shared memory beyond ~8 KiB a 64-thread group cuts the groups an SM holds more than the stack
// saves. (Stacks of 106 KiB at 1024 threads lost the device.) Those were the tree as built; the
// reinserted tree is deeper (the atrium's binary stack 25 → 33 entries, 8.25 KiB at 64 threads), so
// its any-hit stacks went to local memory too, measured in the same run as the new tree
// (results/h200/tracer-51/reinsert: the binary tree's frame passes gained from both).
inline bool traceStackShared(const TraceBvh& bvh, uint32_t threads, bool closest = false) {
  return uint64_t(bvh.stack) * threads * (closest ? 8 : 4) <= 8192;
}
// The specialization constants compute_occluded.glsl.inc takes, in order: the stack's entries,
// whether it is in shared memory for a workgroup of `threads`, and the width (2, 4 or 8).
inline std::vector<uint32_t> traceBvhSpec(const TraceBvh& bvh, uint32_t threads, bool closest) {
  return {bvh.stack, traceStackShared(bvh, threads, closest) ? 1u : 0u, bvh.width};
}

}  // namespace hb
