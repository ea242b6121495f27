// The bounding-volume hierarchy that primary visibility's frusta traverse (Davidovic et al. 2012,
// Sect. 4: "3DR frustum cull", "frustum split", "full"), built once per scene on the CPU and
// uploaded as gpu::PrimaryBvhNode (shaders/raster3d_bvh.comp.glsl).
//  - Binary, binned SAH over the triangles' centroids (BvhBuildOptions: 12 bins on the widest axis
//    by default, the cheaper of the best split and a leaf), leaves of at most kPrimaryBvhLeaf triangles (a leaf the SAH
//    would keep larger is cut at the median of its widest axis).
//  - Depth-first order: an interior node's left child follows it, its right child is `right`.
//  - Every node holds the range [first, first + count) of `order` that its subtree's triangles
//    occupy, so a node can be rasterized whole (the traversal's fallback when its stack is full)
//    and culling can count the triangles it removed.
//  - Boxes are the exact float min and max of the float vertices (no rounding), so a box holds
//    every triangle of its subtree exactly. A triangle with a non-finite vertex covers no pixel
//    (its setup fails): it sits in a leaf but adds nothing to any box.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "shared/gpu_types.h"

namespace hb {

inline constexpr uint32_t kPrimaryBvhLeaf = 4;

struct PrimaryBvh {
  std::vector<gpu::PrimaryBvhNode> nodes;  // [0] is the root
  std::vector<uint32_t> order;             // triangle ids (draw order) in leaf order
  uint32_t depth = 0;                      // the longest root-to-leaf path, in nodes
  double buildMs = 0.0;                    // wall time of the build on the CPU
};

// How the SAH builds: bins an axis, and whether it tries every axis or only the centroids' widest.
// The default is primary visibility's tree; the ray tracer's is kTraceBvhBuild (trace_bvh.h).
struct BvhBuildOptions {
  int bins = 12;
  bool allAxes = false;
  uint32_t reinsertRounds = 0;  // then rounds of reinsertion (bvh_reinsert.h); 0: the SAH build as it is
};

// `vertices`: 3 per triangle, world space (Scene::worldTriangles()).
PrimaryBvh buildPrimaryBvh(const std::vector<glm::vec3>& vertices, const BvhBuildOptions& options = {});

}  // namespace hb
