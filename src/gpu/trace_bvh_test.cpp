// The compute backend's BVH as uploaded (trace_bvh.h), checked on the CPU, so the sanitizers see
// its build: every triangle once with its exact vertices and id, boxes that hold their subtrees
// exactly, a stack as deep as any path needs, the same for the tree collapsed to 4 and 8 children
// (bvh_width=4, 8), and a traversal of each layout that finds the same nearest triangle as testing
// every triangle.
#include "gpu/trace_bvh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "base/parallel_test_util.h"
#include "gltf/gltf_io.h"
#include "gpu/bvh_reinsert.h"
#include "scene/atrium.h"

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

// The wide tree below `node`: every child's box, as the shader decodes it (trace_bvh.h wideChild),
// holds every triangle of its subtree; leaves hold at most 8 triangles; marks each slot a leaf covers
// in `covered`; returns the subtree's depth in nodes, and widens `lo`, `hi` to its triangles.
uint32_t checkWide(const TraceBvhLayout& l, uint32_t node, std::vector<int>& covered, glm::vec3& lo, glm::vec3& hi) {
  uint32_t deepest = 0;
  for (uint32_t k = 0; k < l.width; ++k) {
    const WideChild c = wideChild(l.wide, l.width, node, k);
    if (c.code == kWideEmpty) continue;
    glm::vec3 subLo(std::numeric_limits<float>::max()), subHi(-std::numeric_limits<float>::max());
    if (c.code & kWideLeaf) {
      const uint32_t first = c.code & 0x0FFFFFFFu, count = ((c.code >> 28) & 7u) + 1;
      for (uint32_t s = first; s < first + count; ++s) {
        ++covered.at(s);
        bool finite = true;
        for (int j = 0; j < 3; ++j) {
          const glm::vec3 p = glm::vec3(l.triangles[3 * size_t(s) + j]);
          finite = finite && std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
        }
        for (int j = 0; j < 3 && finite; ++j) {
          subLo = glm::min(subLo, glm::vec3(l.triangles[3 * size_t(s) + j]));
          subHi = glm::max(subHi, glm::vec3(l.triangles[3 * size_t(s) + j]));
        }
      }
    } else {
      EXPECT_GT(c.code, node) << "children after their parent";
      deepest = std::max(deepest, checkWide(l, c.code, covered, subLo, subHi));
    }
    if (subLo.x <= subHi.x) {
      EXPECT_TRUE(glm::all(glm::lessThanEqual(c.lo, subLo)) && glm::all(glm::greaterThanEqual(c.hi, subHi)))
          << "wide node " << node << " child " << k << ": its box does not hold its triangles";
    }
    lo = glm::min(lo, subLo);
    hi = glm::max(hi, subHi);
  }
  return 1 + deepest;
}

void checkWideLayout(const std::vector<glm::vec3>& v, uint32_t width) {
  SCOPED_TRACE("width " + std::to_string(width));
  const TraceBvhLayout l = layoutTraceBvh(v, width);
  ASSERT_EQ(l.width, width);
  ASSERT_EQ(l.wide.size() % wideNodeVec4s(width), 0u);
  ASSERT_GE(l.wide.size(), wideNodeVec4s(width));
  EXPECT_EQ(l.nodeBytes(), l.wide.size() * sizeof(glm::vec4));
  std::vector<int> covered(v.size() / 3, 0);
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  const uint32_t depth = checkWide(l, 0, covered, lo, hi);
  for (size_t s = 0; s < covered.size(); ++s) EXPECT_EQ(covered[s], 1) << "slot " << s;
  EXPECT_EQ(depth, l.depth);
  EXPECT_EQ(l.stack, (width - 1) * depth);  // up to width − 1 children pushed a level
  // The same triangles in the same order as the binary layout: the wide tree only regroups its nodes.
  const TraceBvhLayout b = layoutTraceBvh(v, 2);
  ASSERT_EQ(b.triangles.size(), l.triangles.size());
  if (!b.triangles.empty()) {  // memcmp of an empty vector's null data is undefined (UBSan)
    EXPECT_EQ(std::memcmp(b.triangles.data(), l.triangles.data(), b.triangles.size() * sizeof(glm::vec4)), 0);
  }
  if (v.size() >= 3 * 64) {
    EXPECT_LT(depth, b.depth);  // shallower (about half where the binary tree is balanced)
    if (width == 8) {
      EXPECT_LE(depth, layoutTraceBvh(v, 4).depth);
    }
  }
}

void checkLayout(const std::vector<glm::vec3>& v, const std::string& what) {
  SCOPED_TRACE(what);
  checkWideLayout(v, 4);
  checkWideLayout(v, 8);
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

// The same through the wide tree's boxes.
void wideSlotsAlong(const TraceBvhLayout& l, uint32_t node, const glm::dvec3& o, const glm::dvec3& d,
                    std::vector<uint32_t>& out) {
  for (int k = 0; k < int(l.width); ++k) {
    const WideChild c = wideChild(l.wide, l.width, node, uint32_t(k));
    const uint32_t code = c.code;
    if (code == kWideEmpty) continue;
    const glm::vec3 lo = c.lo, hi = c.hi;
    double t0 = 0, t1 = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
      const double inv = 1.0 / d[a];
      double x = (lo[a] - o[a]) * inv, y = (hi[a] - o[a]) * inv;
      if (x > y) std::swap(x, y);
      t0 = std::max(t0, x);
      t1 = std::min(t1, y);
    }
    if (t0 > t1) continue;
    if (code & kWideLeaf) {
      const uint32_t first = code & 0x0FFFFFFFu, count = ((code >> 28) & 7u) + 1;
      for (uint32_t s = first; s < first + count; ++s) out.push_back(s);
    } else {
      wideSlotsAlong(l, code, o, d, out);
    }
  }
}

TEST(TraceBvh, EveryTriangleOnceInBoxesThatHoldThem) {
  for (const char* name : {"scenes/cornell-box.gltf", "scenes/external/mcad-gears.glb", "scenes/degenerate.gltf",
                           "scenes/tiny-triangles.glb"}) {
    const Scene scene = loadGltf(std::string(HYBRIDBENCH_SOURCE_DIR "/") + name);
    checkLayout(scene.worldTriangles(), name);
  }
}

// The wide tree's SAH cost as the collapse minimizes it (trace_bvh.cpp SahCollapse::solve): each wide node
// below the root its box's half area, each leaf its box's half area times its triangles.
double wideSahCost(const TraceBvhLayout& l, uint32_t node) {
  double cost = 0;
  for (uint32_t k = 0; k < l.width; ++k) {
    const WideChild c = wideChild(l.wide, l.width, node, k);
    if (c.code == kWideEmpty) continue;
    const glm::vec3 d = glm::max(c.hi - c.lo, glm::vec3(0.0f));
    const double area = double(d.x * d.y + d.y * d.z + d.z * d.x);
    if (c.code & kWideLeaf)
      cost += area * double(((c.code >> 28) & 7u) + 1);
    else
      cost += area + wideSahCost(l, c.code);
  }
  return cost;
}

// The same cost for the collapse the tracer used before the one of least SAH cost: a node's children start as
// its binary node's two, and while fewer than W, the interior child with the largest box opens.
double greedyCollapseCost(const std::vector<gpu::PrimaryBvhNode>& b, uint32_t node, uint32_t width) {
  const auto area = [&](uint32_t n) {
    const glm::vec3 d = glm::max(glm::vec3(b[n].hi) - glm::vec3(b[n].lo), glm::vec3(0.0f));
    return double(d.x * d.y + d.y * d.z + d.z * d.x);
  };
  std::vector<uint32_t> kids = {node + 1, b[node].info.x};
  while (kids.size() < width) {
    int widest = -1;
    for (size_t i = 0; i < kids.size(); ++i)
      if (b[kids[i]].info.x != 0 && (widest < 0 || area(kids[i]) > area(kids[size_t(widest)]))) widest = int(i);
    if (widest < 0) break;
    const uint32_t k = kids[size_t(widest)];
    kids[size_t(widest)] = k + 1;
    kids.insert(kids.begin() + widest + 1, b[k].info.x);
  }
  double cost = 0;
  for (uint32_t k : kids)
    cost += b[k].info.x == 0 ? area(k) * double(b[k].info.z) : area(k) + greedyCollapseCost(b, k, width);
  return cost;
}

// The binary tree is collapsed to the wide tree of least SAH cost (Ylitie et al. 2017): on the
// atrium and an external CAD mesh, at widths 4 and 8, the layout costs less than the greedy collapse
// of the same binary tree, which is one of the trees the search weighs: made to fail once by
// choosing each split's worst share instead of its best.
TEST(TraceBvh, TheWideTreeCostsLessThanTheGreedyCollapse) {
  const Scene gears = loadGltf(HYBRIDBENCH_SOURCE_DIR "/scenes/external/mcad-gears.glb");
  for (const auto& [name, v] : {std::pair<std::string, std::vector<glm::vec3>>{"atrium", makeAtrium().worldTriangles()},
                                {"mcad-gears", gears.worldTriangles()}}) {
    for (uint32_t width : {4u, 8u}) {
      SCOPED_TRACE(name + " width " + std::to_string(width));
      const TraceBvhLayout l = layoutTraceBvh(v, width);
      const double ours = wideSahCost(l, 0), greedy = greedyCollapseCost(l.nodes, 0, width);
      EXPECT_LT(ours, greedy);
      std::printf("[ info ] %s width %u: SAH cost %.6g, greedy collapse %.6g (%.2f %%)\n", name.c_str(), width, ours,
                  greedy, 100.0 * (ours / greedy - 1.0));
    }
  }
}

// The build splits the top of the tree on one thread and builds its subtrees on many
// (primary_bvh.cpp ParallelBuild): the tree is the one the serial build makes, bit for bit. The
// atrium (262,028 triangles) has subtrees enough for the parallel path; both builds' options.
TEST(TraceBvh, TheTreeIsTheSameBitForBitOnOneThreadAndOnSeveral) {
  const std::vector<glm::vec3> v = makeAtrium().worldTriangles();
  for (const BvhBuildOptions& options : {BvhBuildOptions{}, kTraceBvhBuild}) {
    PrimaryBvh one, several;
    {
      ScopedAnalysisThreads threads(1u);
      one = buildPrimaryBvh(v, options);
    }
    {
      ScopedAnalysisThreads threads(4u);
      several = buildPrimaryBvh(v, options);
    }
    ASSERT_EQ(one.nodes.size(), several.nodes.size()) << options.bins;
    EXPECT_EQ(std::memcmp(one.nodes.data(), several.nodes.data(), one.nodes.size() * sizeof(one.nodes[0])), 0)
        << options.bins;
    EXPECT_EQ(one.order, several.order) << options.bins;
    EXPECT_EQ(one.depth, several.depth) << options.bins;
  }
}

// The tracer's tree is optimized by reinsertion (bvh_reinsert.h, kTraceBvhBuild): on the atrium it
// must cost less than the tree as built, by the cost it reports; every interior box must be exactly
// its children's union (a box left as it was before a subtree moved out still holds its subtree, so
// only equality shows a missed refit); and the leaves must be the built tree's leaves, moved whole.
TEST(TraceBvh, ReinsertionLowersTheSahCostAndMovesLeavesWhole) {
  const std::vector<glm::vec3> v = makeAtrium().worldTriangles();
  BvhBuildOptions asBuilt = kTraceBvhBuild;
  asBuilt.reinsertRounds = 0;
  const PrimaryBvh built = buildPrimaryBvh(v, asBuilt);
  PrimaryBvh tree = built;
  const BvhReinsertStats stats = reinsertBvh(tree, kTraceBvhBuild.reinsertRounds);
  EXPECT_EQ(stats.costBefore, bvhSahCost(built));
  EXPECT_EQ(stats.costAfter, bvhSahCost(tree));
  EXPECT_LT(stats.costAfter, stats.costBefore);
  EXPECT_GT(stats.reinserted, 0u);
  EXPECT_EQ(stats.depthAfter, tree.depth);
  ASSERT_EQ(tree.nodes.size(), built.nodes.size());
  const auto leaves = [](const PrimaryBvh& t) {
    std::vector<std::vector<uint32_t>> out;
    for (const gpu::PrimaryBvhNode& n : t.nodes)
      if (n.info.x == 0) out.emplace_back(t.order.begin() + n.info.y, t.order.begin() + n.info.y + n.info.z);
    std::sort(out.begin(), out.end());
    return out;
  };
  EXPECT_EQ(leaves(tree), leaves(built));
  int unions = 0;
  for (size_t i = 0; i < tree.nodes.size(); ++i) {
    const gpu::PrimaryBvhNode& n = tree.nodes[i];
    if (n.info.x == 0) continue;
    const gpu::PrimaryBvhNode &l = tree.nodes[i + 1], &r = tree.nodes[n.info.x];
    const bool exact = glm::vec3(n.lo) == glm::min(glm::vec3(l.lo), glm::vec3(r.lo)) &&
                       glm::vec3(n.hi) == glm::max(glm::vec3(l.hi), glm::vec3(r.hi));
    unions += exact;
    EXPECT_TRUE(exact) << "node " << i;
    if (!exact) break;
  }
  EXPECT_GT(unions, 1000);
  // A layout of it is still every triangle once, in boxes that hold them, at every width.
  checkLayout(v, "the atrium, reinserted");
}

// Trees with no node to reinsert (every interior node the root or a child of it) and barely more:
// reinsertion leaves them as valid as it found them. Four, eight and sixteen triangles in a row
// (leaves of up to 4: the root alone, the root and two leaves, and seven nodes).
TEST(TraceBvh, ReinsertionOfSmallTreesIsSafe) {
  for (int count : {4, 8, 12, 16, 24}) {
    std::vector<glm::vec3> v;
    for (int i = 0; i < count; ++i) v.insert(v.end(), {{float(i), 0, 0}, {float(i) + 1, 0, 0}, {float(i), 1, 0}});
    BvhBuildOptions asBuilt = kTraceBvhBuild;
    asBuilt.reinsertRounds = 0;
    PrimaryBvh tree = buildPrimaryBvh(v, asBuilt);
    const size_t nodes = tree.nodes.size();
    const BvhReinsertStats stats = reinsertBvh(tree, kTraceBvhBuild.reinsertRounds);
    EXPECT_EQ(tree.nodes.size(), nodes) << count;
    EXPECT_LE(stats.costAfter, stats.costBefore * (1 + 1e-12)) << count;
    checkLayout(v, std::to_string(count) + " triangles in a row");
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
  // Finite but huge: boxes 4e20 wide, whose half area overflows a float (the collapse weighs them in
  // double; in float every cost above 8 triangles was infinite and the root's child became a leaf
  // of 40, which the leaf code cannot hold).
  std::vector<glm::vec3> huge;
  for (int i = 0; i < 40; ++i) {
    const float x = float(i) * 1e19f;
    huge.insert(huge.end(), {{x, 0, 0}, {x + 1e19f, 0, 1e20f}, {x, 1e20f, 0}});
  }
  checkLayout(huge, "coordinates near 1e20");
}

// Subtrees the binary build must split (it keeps at most 4 triangles a leaf) become one wide leaf
// of up to 8 where that costs less: W clusters of 8 triangles that overlap almost whole, 100 m apart,
// for width W. A cluster as one leaf costs 8 half areas A; as a wide node, A more than its leaves;
// as two of the root's slots, W clusters would need 2W. So the root holds W leaves of 8. Rays
// through every cluster find brute force's nearest triangle through the merged leaves. Fails if the
// collapse keeps the binary leaves (no leaf over 4).
TEST(TraceBvh, TheCollapseMergesSmallSubtreesIntoLeavesOfUpToEight) {
  for (uint32_t width : {4u, 8u}) {
    SCOPED_TRACE("width " + std::to_string(width));
    std::vector<glm::vec3> v;
    for (uint32_t c = 0; c < width; ++c)
      for (int i = 0; i < 8; ++i) {
        const float cx = 100.0f * float(c), e = 0.001f * float(i);  // nearly the same triangle
        v.insert(v.end(), {{cx + e, e, 0}, {cx + 1 + e, 0, e}, {cx, 1 + e, 0.5f}});
      }
    checkLayout(v, std::to_string(width) + " clusters of 8");
    const TraceBvhLayout l = layoutTraceBvh(v, width);
    for (uint32_t k = 0; k < width; ++k) {
      const WideChild c = wideChild(l.wide, width, 0, k);
      ASSERT_NE(c.code, kWideEmpty) << "slot " << k;
      ASSERT_TRUE(c.code & kWideLeaf) << "slot " << k;
      EXPECT_EQ(((c.code >> 28) & 7u) + 1, 8u) << "slot " << k;
    }
    std::vector<uint32_t> all(v.size() / 3);
    for (uint32_t s = 0; s < all.size(); ++s) all[s] = s;
    for (int r = 0; r < 64; ++r) {
      const glm::dvec3 o(100.0 * (r % int(width)) + 0.1 + 0.005 * r, 0.1 + 0.004 * r, -5.0), d(0, 0, 1);
      double tAll = 1e30, tWide = 1e30;
      std::vector<uint32_t> slots;
      wideSlotsAlong(l, 0, o, d, slots);
      const int brute = nearestOf(l, all, o, d, tAll);
      EXPECT_GE(brute, 0) << "ray " << r;
      EXPECT_EQ(nearestOf(l, slots, o, d, tWide), brute) << "ray " << r;
    }
  }
}

// The tracer's SAH tries every axis (kTraceBvhBuild), not only the centroids' widest: two rows of
// small triangles 10 m apart in y, each 100 m long in x. The widest extent is x, and a cut across it
// leaves both halves 10 m tall; the cheaper cut is between the rows (half areas of about 120 against
// 571 a child, derived below), which only a build that tries y finds. Primary visibility's tree keeps
// its default (the widest axis) and cuts across x: the contrast shows the test can fail.
TEST(TraceBvh, TheTracersSahTriesEveryAxis) {
  std::vector<glm::vec3> v;
  for (int row = 0; row < 2; ++row)
    for (int i = 0; i < 64; ++i) {
      const glm::vec3 o(100.0f * float(i) / 63.0f, 10.0f * float(row), float(i % 2));
      v.insert(v.end(), {o, o + glm::vec3(0.1f, 0.0f, 0.0f), o + glm::vec3(0.0f, 0.1f, 0.1f)});
    }
  // Child half areas dx·dy + dy·dz + dz·dx: between the rows about 100·0.1 + 0.1·1.1 + 1.1·100 = 120;
  // across x about 50·10.1 + 10.1·1.1 + 1.1·50 = 571.
  const auto rootCut = [](const std::vector<gpu::PrimaryBvhNode>& n) {
    const gpu::PrimaryBvhNode &l = n[1], &r = n[n[0].info.x];
    return std::pair<bool, bool>(l.hi.y < r.lo.y || r.hi.y < l.lo.y, l.hi.x < r.lo.x || r.hi.x < l.lo.x);
  };
  BvhBuildOptions sahOnly = kTraceBvhBuild;  // the SAH build alone, before any reinsertion
  sahOnly.reinsertRounds = 0;
  const TraceBvhLayout trace = layoutTraceBvh(v, 2, sahOnly);
  ASSERT_NE(trace.nodes[0].info.x, 0u);
  EXPECT_EQ(rootCut(trace.nodes), std::make_pair(true, false)) << "the tracer's root separates the rows (y)";
  const PrimaryBvh primary = buildPrimaryBvh(v);
  ASSERT_NE(primary.nodes[0].info.x, 0u);
  EXPECT_EQ(rootCut(primary.nodes), std::make_pair(false, true)) << "primary visibility's cuts x, its widest";
  checkLayout(v, "two rows");
}

// Culling by the layout's boxes (binary and wide) loses no nearest hit: the traversal's premise.
TEST(TraceBvh, BoxesLoseNoNearestHit) {
  const Scene scene = loadGltf(HYBRIDBENCH_SOURCE_DIR "/scenes/external/mcad-gears.glb");
  const TraceBvhLayout l = layoutTraceBvh(scene.worldTriangles());
  const TraceBvhLayout wide = layoutTraceBvh(scene.worldTriangles(), 4);
  const TraceBvhLayout wide8 = layoutTraceBvh(scene.worldTriangles(), 8);
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
    std::vector<uint32_t> wideSlots;
    wideSlotsAlong(wide, 0, o, d, wideSlots);
    double tWide = 1e30;
    EXPECT_EQ(nearestOf(wide, wideSlots, o, d, tWide), brute) << "ray " << r << " (width 4)";
    std::vector<uint32_t> wide8Slots;
    wideSlotsAlong(wide8, 0, o, d, wide8Slots);
    double tWide8 = 1e30;
    EXPECT_EQ(nearestOf(wide8, wide8Slots, o, d, tWide8), brute) << "ray " << r << " (width 8)";
    hits += brute >= 0;
  }
  EXPECT_GT(hits, 100);                         // the rays start inside the bounds: most meet a gear
  EXPECT_LT(boxes, 400u * l.nodes.size() / 4);  // and the boxes cull most of the tree
}

}  // namespace
}  // namespace hb
