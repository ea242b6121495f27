// The compute backend's BVH as uploaded (trace_bvh.h), checked on the CPU, so the sanitizers see
// its build: every triangle once with its exact vertices and id, boxes that hold their subtrees
// exactly, a stack as deep as any path needs, and a traversal of the layout that finds the same
// nearest triangle as testing every triangle.
#include "frame/passes/trace_bvh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "scene/gltf/gltf_io.h"

namespace hb {
namespace {

bool boxHolds(const gpu::PrimaryBvhNode& n, const glm::vec3& p) {
  return p.x >= n.lo.x && p.y >= n.lo.y && p.z >= n.lo.z && p.x <= n.hi.x && p.y <= n.hi.y && p.z <= n.hi.z;
}

// Walks the tree from `node`: checks the boxes and ranges, returns the subtree's depth in nodes.
uint32_t checkSubtree(const TraceBvhLayout& l, uint32_t node, uint32_t& leafSlots) {
  const gpu::PrimaryBvhNode& n = l.nodes[node];
  if (n.info.x == 0) {
    for (uint32_t s = n.info.y; s < n.info.y + n.info.z; ++s) {
      EXPECT_EQ(s, leafSlots) << "leaves hold consecutive slots in depth-first order";
      ++leafSlots;
      // A triangle with a non-finite vertex adds nothing to any box (primary_bvh.h); no ray hits it.
      bool finite = true;
      for (int k = 0; k < 3; ++k) {
        const glm::vec3 v = glm::vec3(l.triangles[3 * size_t(s) + k]);
        finite = finite && std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
      }
      for (int k = 0; k < 3 && finite; ++k) {
        EXPECT_TRUE(boxHolds(n, glm::vec3(l.triangles[3 * size_t(s) + k]))) << "node " << node << " slot " << s;
      }
    }
    return 1;
  }
  const uint32_t left = node + 1, right = n.info.x;
  for (uint32_t c : {left, right}) {
    EXPECT_TRUE(boxHolds(n, glm::vec3(l.nodes[c].lo)) && boxHolds(n, glm::vec3(l.nodes[c].hi)))
        << "child " << c << " of " << node;
  }
  EXPECT_EQ(l.nodes[left].info.y, n.info.y);
  EXPECT_EQ(l.nodes[left].info.z + l.nodes[right].info.z, n.info.z);
  EXPECT_EQ(l.nodes[right].info.y, n.info.y + l.nodes[left].info.z);
  const uint32_t leftDepth = checkSubtree(l, left, leafSlots);  // left first: the slots' order
  return 1 + std::max(leftDepth, checkSubtree(l, right, leafSlots));
}

void checkLayout(const std::vector<glm::vec3>& v, const std::string& what) {
  SCOPED_TRACE(what);
  const TraceBvhLayout l = layoutTraceBvh(v);
  const size_t triangles = v.size() / 3;
  ASSERT_EQ(l.triangles.size(), 3 * triangles);
  std::vector<int> seen(triangles, 0);
  for (size_t s = 0; s < triangles; ++s) {
    const uint32_t id = traceBvhTriangleId(l, s);
    ASSERT_LT(id, triangles);
    ++seen[id];
    for (int k = 0; k < 3; ++k)  // the vertices bit for bit, so our hits are the scene's
      EXPECT_EQ(std::memcmp(&l.triangles[3 * s + k], &v[3 * size_t(id) + k], sizeof(glm::vec3)), 0);
    EXPECT_EQ(l.triangles[3 * s + 1].w, 1.0f);
    EXPECT_EQ(l.triangles[3 * s + 2].w, 1.0f);
  }
  for (size_t id = 0; id < triangles; ++id) EXPECT_EQ(seen[id], 1) << "triangle " << id;
  if (triangles == 0) return;
  uint32_t slots = 0;
  const uint32_t depth = checkSubtree(l, 0, slots);
  EXPECT_EQ(slots, triangles);
  EXPECT_EQ(depth, l.depth);
  // A path pushes at most one node per interior level: depth − 1 entries (at least 1 allocated).
  EXPECT_EQ(l.stack, std::max(1u, depth - 1));
}

// Nearest hit in double over the given slots (Möller–Trumbore, both faces): slot or -1.
int nearestOf(const TraceBvhLayout& l, const std::vector<uint32_t>& slots, const glm::dvec3& o, const glm::dvec3& d,
              double& tBest) {
  int best = -1;
  for (uint32_t s : slots) {
    const glm::dvec3 a(l.triangles[3 * size_t(s)]), b(l.triangles[3 * size_t(s) + 1]),
        c(l.triangles[3 * size_t(s) + 2]);
    const glm::dvec3 e1 = b - a, e2 = c - a, p = glm::cross(d, e2);
    const double det = glm::dot(e1, p);
    if (det == 0.0) continue;
    const glm::dvec3 q = o - a;
    const double u = glm::dot(q, p) / det;
    const glm::dvec3 r = glm::cross(q, e1);
    const double w = glm::dot(d, r) / det, t = glm::dot(e2, r) / det;
    if (u < 0 || w < 0 || u + w > 1 || t <= 0 || t >= tBest) continue;
    tBest = t;
    best = int(s);
  }
  return best;
}

// The slots whose leaves' boxes the ray meets (a box test in double, no culling by distance).
void leafSlotsAlong(const TraceBvhLayout& l, uint32_t node, const glm::dvec3& o, const glm::dvec3& d,
                    std::vector<uint32_t>& out, uint32_t& boxes) {
  const gpu::PrimaryBvhNode& n = l.nodes[node];
  ++boxes;
  double t0 = 0, t1 = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    const double inv = 1.0 / d[k];
    double a = (n.lo[k] - o[k]) * inv, b = (n.hi[k] - o[k]) * inv;
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
  }
  if (t0 > t1) return;
  if (n.info.x == 0) {
    for (uint32_t s = n.info.y; s < n.info.y + n.info.z; ++s) out.push_back(s);
    return;
  }
  leafSlotsAlong(l, node + 1, o, d, out, boxes);
  leafSlotsAlong(l, n.info.x, o, d, out, boxes);
}

TEST(TraceBvh, EveryTriangleOnceInBoxesThatHoldThem) {
  for (const char* name : {"scenes/cornell-box.gltf", "scenes/external/mcad-gears.glb", "scenes/degenerate.gltf",
                           "scenes/tiny-triangles.glb"}) {
    const Scene scene = loadGltf(std::string(HYBRIDBENCH_SOURCE_DIR "/") + name);
    checkLayout(scene.worldTriangles(), name);
  }
}

TEST(TraceBvh, EdgeCases) {
  checkLayout({}, "no triangle");
  checkLayout({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, "one triangle");
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<glm::vec3> v;
  for (int i = 0; i < 40; ++i) v.insert(v.end(), {{float(i), 0, 0}, {float(i) + 1, 0, 0}, {float(i), 1, 0}});
  v[3 * 7] = glm::vec3(nan, 0, 0);            // a triangle with a non-finite vertex sits in a leaf, in no box
  v.insert(v.end(), 30, glm::vec3(2, 2, 2));  // ten triangles collapsed to one point
  checkLayout(v, "a row, a NaN vertex, collapsed triangles");
}

// Culling by the layout's boxes loses no nearest hit: the traversal's premise.
TEST(TraceBvh, BoxesLoseNoNearestHit) {
  const Scene scene = loadGltf(HYBRIDBENCH_SOURCE_DIR "/scenes/external/mcad-gears.glb");
  const TraceBvhLayout l = layoutTraceBvh(scene.worldTriangles());
  glm::vec3 lo, hi;
  scene.bounds(lo, hi);
  std::vector<uint32_t> all(l.triangles.size() / 3);
  for (uint32_t s = 0; s < all.size(); ++s) all[s] = s;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int hits = 0;
  uint64_t boxes = 0;
  for (int r = 0; r < 400; ++r) {
    const glm::dvec3 o = glm::mix(glm::dvec3(lo), glm::dvec3(hi), glm::dvec3(u(rng), u(rng), u(rng)));
    const double z = 2 * u(rng) - 1, phi = 6.283185307179586 * u(rng), s = std::sqrt(1 - z * z);
    const glm::dvec3 d(s * std::cos(phi), s * std::sin(phi), z);
    double tAll = 1e30, tTree = 1e30;
    const int brute = nearestOf(l, all, o, d, tAll);
    std::vector<uint32_t> slots;
    uint32_t visited = 0;
    leafSlotsAlong(l, 0, o, d, slots, visited);
    boxes += visited;
    const int tree = nearestOf(l, slots, o, d, tTree);
    EXPECT_EQ(tree, brute) << "ray " << r;
    hits += brute >= 0;
  }
  EXPECT_GT(hits, 100);                         // the rays start inside the bounds: most meet a gear
  EXPECT_LT(boxes, 400u * l.nodes.size() / 4);  // and the boxes cull most of the tree
}

}  // namespace
}  // namespace hb
