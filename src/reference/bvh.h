// CPU bounding-volume hierarchy over world-space triangles, in double precision, for the shadow
// reference (oracle and visibility checks). Ray/triangle test: Woop, Benthin, Wald 2013,
// "Watertight Ray/Triangle Intersection" (JCGT 2(1)): a ray through a shared edge or vertex of a
// closed mesh always hits at least one of the triangles that share it.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace hb {

struct BvhTriangle {
  glm::dvec3 v0, v1, v2;
};

// Zero area up to rounding: |cross(e1, e2)| <= 8 eps |e1| |e2| (the cross product's own rounding
// error is about 2 eps |e1||e2|, so anything below is indistinguishable from collinear), or a
// non-finite vertex. Such triangles are dropped when building and never hit.
bool isDegenerate(const BvhTriangle& tri);

// Watertight test, both faces. Hits iff the ray meets the closed triangle (edges included) at
// t in [tMin, tMax]; then writes t. Degenerate triangles (isDegenerate) and a zero `dir` never hit;
// no NaN escapes (every NaN comparison falls to "miss").
bool intersectTriangleWatertight(const BvhTriangle& tri, const glm::dvec3& origin, const glm::dvec3& dir, double tMin,
                                 double tMax, double& t);

struct BvhHit {
  double t;
  uint32_t triangle;  // index in the list the Bvh was built from
};

class Bvh {
 public:
  Bvh() = default;
  // Median split on the widest centroid axis, leaves of at most 4 triangles. Degenerate triangles
  // are dropped (droppedDegenerate() counts them).
  explicit Bvh(std::vector<BvhTriangle> triangles);

  // Any hit with t in [tMin, tMax] (opaque, both faces, first hit ends the search), as a shadow
  // ray with gl_RayFlagsTerminateOnFirstHitEXT | gl_RayFlagsOpaqueEXT. dir need not be unit.
  bool occluded(const glm::dvec3& origin, const glm::dvec3& dir, double tMin, double tMax) const;
  // Nearest hit in [tMin, tMax]; false when none.
  bool closestHit(const glm::dvec3& origin, const glm::dvec3& dir, double tMin, double tMax, double& t) const;
  // The same, and which triangle: its index in the list the Bvh was built from.
  bool closestHit(const glm::dvec3& origin, const glm::dvec3& dir, double tMin, double tMax, double& t,
                  uint32_t& triangle) const;

  // Every hit with t in [tMin, tMax], one per triangle the watertight test accepts (a line
  // through an edge or vertex shared by several triangles may hit each of them), sorted by t,
  // ties by triangle index. Replaces the contents of `hits`. tMin = -inf gives the whole line.
  void allHits(const glm::dvec3& origin, const glm::dvec3& dir, double tMin, double tMax,
               std::vector<BvhHit>& hits) const;

  size_t triangleCount() const { return triangles_.size(); }
  size_t droppedDegenerate() const { return dropped_; }
  // The triangles kept (degenerate ones dropped), in the tree's order.
  const std::vector<BvhTriangle>& triangles() const { return triangles_; }
  // Triangle `index` of the list the Bvh was built from (degenerate ones included).
  const BvhTriangle& input(uint32_t index) const { return inputs_[index]; }

 private:
  struct Node {
    glm::dvec3 lo, hi;
    uint32_t firstOrRight;  // leaf: first triangle; interior: right child (left = this + 1)
    uint32_t count;         // > 0: leaf
  };
  uint32_t build(uint32_t first, uint32_t count, std::vector<glm::dvec3>& centroids);
  template <bool AnyHit>
  bool traverse(const glm::dvec3& origin, const glm::dvec3& dir, double tMin, double tMax, double& t,
                uint32_t& triangle) const;
  // Visits every kept triangle i whose leaf box the ray meets within [tMin, tFar] (tFar read again
  // at each box, so a caller that shortens it prunes the rest); `onTriangle(i)` returns false to stop.
  template <class OnTriangle>
  void walk(const glm::dvec3& origin, const glm::dvec3& dir, double tMin, const double& tFar,
            OnTriangle onTriangle) const;

  std::vector<BvhTriangle> inputs_;     // as passed
  std::vector<BvhTriangle> triangles_;  // kept, in tree order
  std::vector<uint32_t> ids_;           // triangles_[i] is inputs_[ids_[i]]
  std::vector<Node> nodes_;
  size_t dropped_ = 0;
};

// Flattens every instance × primitive of the scene into world-space triangles (object positions
// transformed by the instance matrix in double). Precondition: the scene's indices are in range
// (HB_ASSERT otherwise).
Bvh buildBvh(const Scene& scene);

}  // namespace hb
