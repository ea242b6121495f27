// Splitting the references of large triangles before the SAH build (early split clipping, Ernst
// and Greiner 2007; the splitting planes of Karras and Aila 2013, "Fast parallel construction of
// high-quality bounding volume hierarchies"). A triangle whose box is large (a floor or a wall of two
// triangles) makes every node above it large: each ray that passes near it visits them. Splitting
// gives such a triangle several references, each the box of the part of the triangle inside one
// piece of its box, so the build can place the pieces in tight subtrees. A triangle may then sit in
// several leaves; a ray tests it in each leaf it reaches (the nearest hit is the same triangle).
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace hb {

// One reference of a triangle: a box that holds the part of the triangle inside it. The boxes of a
// triangle's references together hold all of it. An empty box (lo > hi): a triangle with a
// non-finite vertex, which is never split.
struct TriangleReference {
  glm::vec3 lo{0.0f}, hi{0.0f};
  uint32_t triangle = 0;
};

struct TriangleSplitStats {
  uint64_t splits = 0;  // references added (each split of one reference into two)
  uint64_t shrunk = 0;  // references whose triangle missed one side: the box shrank, nothing added
};

// The references of the triangles of `vertices` (3 per triangle), in triangle order, then up to
// floor(budget × triangles) more: the reference of the largest box (half surface area; the lower
// index on equal areas) is split next, at the plane of the coarsest level of the scene box's dyadic
// grid that crosses its box's longest axis, and the triangle is clipped (in double) to each side.
// Every box is rounded outward to float and then clamped to the piece it was clipped to, so it holds
// its part of the triangle: the union of a triangle's boxes holds the triangle. Deterministic.
// excessOnly: the priority is the box's area less the triangle's own (bvh_split.cpp priority).
std::vector<TriangleReference> splitTriangleReferences(const std::vector<glm::vec3>& vertices, double budget,
                                                       bool excessOnly = false, TriangleSplitStats* stats = nullptr);

}  // namespace hb
