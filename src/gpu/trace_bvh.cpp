#include "gpu/trace_bvh.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <limits>
#include <vector>

#include "base/errors.h"
#include "gpu/primary_bvh.h"

namespace hb {

namespace {

// In double: a finite box of extents near 1e19 has no float half area (the glTF loader takes any
// finite vertex), and an infinite cost would leave the collapse no finite choice.
double halfAreaOf(const gpu::PrimaryBvhNode& n) {
  const glm::dvec3 d = glm::max(glm::dvec3(glm::vec3(n.hi)) - glm::dvec3(glm::vec3(n.lo)), glm::dvec3(0.0));
  return d.x * d.y + d.y * d.z + d.z * d.x;
}

// The SAH-optimal collapse (Ylitie, Karras and Laine 2017, Sect. 3.1): which binary nodes become
// the wide nodes and which subtrees become leaves, chosen bottom up to minimize the wide tree's SAH
// cost, the sum of each wide node's area times kNodeCost and each leaf's area times its triangles
// times kTriangleCost. cost(n, i) is the least cost of binary subtree n cut into at most i roots,
// each a leaf (a subtree of at most kMaxLeaf triangles: its range of the triangle order is
// contiguous, trace_bvh.h's leaf code holds up to 8) or a wide node whose children are its subtree
// cut into at most W roots. Depth first: a node before its children.
struct SahCollapse {
  const std::vector<gpu::PrimaryBvhNode>& binary;
  std::vector<glm::vec4>& out;
  uint32_t width;
  // The binary build's costs (primary_bvh.cpp: 1 a node traversal, 1 a triangle test). On the H200
  // a cheaper triangle (0.15 to 0.5 of a node) merged more leaves and traced every ray set slower
  // at width 4 (results/h200/tracer-51/collapse); from 1 up the tree is the same but for a few
  // hundred nodes.
  static constexpr double kNodeCost = 1.0, kTriangleCost = 1.0;
  static constexpr uint32_t kMaxLeaf = 8;
  std::vector<double> cost;    // [n · W + i − 1]
  std::vector<uint8_t> split;  // [n · W + i − 1], i ≥ 2: 0 as i − 1 roots, else k: the left child's share
  std::vector<uint8_t> leaf;   // [n]: cost(n, 1) is n as one leaf
  uint32_t depth = 0;

  uint32_t right(uint32_t n) const { return binary[n].info.x; }
  bool isBinaryLeaf(uint32_t n) const { return binary[n].info.x == 0; }
  double c(uint32_t n, uint32_t i) const { return cost[size_t(n) * width + i - 1]; }
  // The best split of i roots between n's children, and its cost.
  std::pair<double, uint32_t> distribute(uint32_t n, uint32_t i) const {
    double best = std::numeric_limits<double>::infinity();
    uint32_t bestK = 1;
    for (uint32_t k = 1; k < i; ++k) {
      const double v = c(n + 1, k) + c(right(n), i - k);
      if (v < best) {
        best = v;
        bestK = k;
      }
    }
    return {best, bestK};
  }

  void solve() {
    const size_t count = binary.size();
    cost.assign(count * width, 0.0);
    split.assign(count * width, 0);
    leaf.assign(count, 0);
    for (size_t m = count; m-- > 0;) {  // a node's children follow it
      const uint32_t n = uint32_t(m);
      const double area = halfAreaOf(binary[n]);
      const uint32_t tris = binary[n].info.z;
      const bool mayLeaf = isBinaryLeaf(n) || (tris >= 1 && tris <= kMaxLeaf);
      const double asLeaf = mayLeaf ? area * double(tris) * kTriangleCost : std::numeric_limits<double>::infinity();
      if (isBinaryLeaf(n)) {
        for (uint32_t i = 1; i <= width; ++i) cost[m * width + i - 1] = asLeaf;
        leaf[m] = 1;
        continue;
      }
      const double asNode = area * kNodeCost + distribute(n, width).first;
      cost[m * width] = std::min(asLeaf, asNode);
      leaf[m] = mayLeaf && asLeaf <= asNode ? 1 : 0;
      // On a tie, more roots: a subtree of no area (triangles collapsed to a point) costs 0 however
      // it is cut, and fuller nodes keep it shallow.
      for (uint32_t i = 2; i <= width; ++i) {
        const auto [v, k] = distribute(n, i);
        if (v <= c(n, i - 1)) {
          cost[m * width + i - 1] = v;
          split[m * width + i - 1] = uint8_t(k);
        } else {
          cost[m * width + i - 1] = c(n, i - 1);
        }
      }
    }
  }

  void roots(uint32_t n, uint32_t i, std::vector<uint32_t>& kids) const {
    while (i >= 2 && !isBinaryLeaf(n) && split[size_t(n) * width + i - 1] == 0) --i;
    if (i == 1 || isBinaryLeaf(n)) {
      kids.push_back(n);
      return;
    }
    const uint32_t k = split[size_t(n) * width + i - 1];
    roots(n + 1, k, kids);
    roots(right(n), i - k, kids);
  }

  // Wide node for binary node b (its subtree cut into at most W roots); returns its index.
  uint32_t build(uint32_t b, uint32_t level) {
    std::vector<uint32_t> kids;
    if (isBinaryLeaf(b)) {
      kids = {b};  // the root is a leaf: one child
    } else {
      const uint32_t k = distribute(b, width).second;
      roots(b + 1, k, kids);
      roots(right(b), width - k, kids);
    }
    const size_t stride = wideNodeVec4s(width);
    const uint32_t index = uint32_t(out.size() / stride);
    out.resize(out.size() + stride, glm::vec4(0.0f));
    depth = std::max(depth, level);
    std::vector<uint32_t> codes(width, kWideEmpty);
    for (size_t i = 0; i < kids.size(); ++i) {
      const gpu::PrimaryBvhNode& k = binary[kids[i]];
      const size_t group = index * stride + (i / 4) * kWideGroupVec4s;  // child i: group i / 4, slot i % 4
      for (int a = 0; a < 3; ++a) {
        out[group + a][int(i % 4)] = k.lo[a];
        out[group + 3 + a][int(i % 4)] = k.hi[a];
      }
      if (leaf[kids[i]]) {
        HB_ASSERT(k.info.z >= 1 && k.info.z <= kMaxLeaf &&
                  uint64_t(k.info.y) + k.info.z <= (1u << 28));  // never kWideEmpty
        codes[i] = kWideLeaf | (k.info.z - 1) << 28 | k.info.y;
      } else {
        codes[i] = build(kids[i], level + 1);
      }
    }
    for (size_t i = 0; i < width; ++i)
      std::memcpy(&out[index * stride + (i / 4) * kWideGroupVec4s + 6][int(i % 4)], &codes[i], sizeof(uint32_t));
    return index;
  }
};

}  // namespace

TraceBvhLayout layoutTraceBvh(const std::vector<glm::vec3>& vertices, uint32_t width, const BvhBuildOptions& build) {
  HB_ASSERT(width == 2 || width == 4 || width == 8);
  const PrimaryBvh tree = buildPrimaryBvh(vertices, build);
  TraceBvhLayout out;
  out.width = width;
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
  if (width != 2) {
    const auto start = std::chrono::steady_clock::now();
    if (tree.nodes.empty() || tree.order.empty()) {
      out.wide.assign(wideNodeVec4s(width), glm::vec4(0.0f));  // a root without children
      const uint32_t empty = kWideEmpty;
      for (uint32_t g = 0; g < width / 4; ++g)
        for (int i = 0; i < 4; ++i) std::memcpy(&out.wide[g * kWideGroupVec4s + 6][i], &empty, sizeof empty);
      out.depth = 1;
    } else {
      SahCollapse c{out.nodes, out.wide, width};
      c.solve();
      c.build(0, 1);
      out.depth = c.depth;
    }
    out.stack = (width - 1) * out.depth;
    out.buildMs += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  }
  return out;
}

WideChild wideChild(const std::vector<glm::vec4>& wide, uint32_t width, uint32_t node, uint32_t k) {
  HB_ASSERT((width == 4 || width == 8) && k < width);
  const size_t b = size_t(node) * wideNodeVec4s(width) + (k / 4) * kWideGroupVec4s;
  const int s = int(k % 4);
  WideChild c;
  std::memcpy(&c.code, &wide[b + 6][s], sizeof c.code);
  c.lo = {wide[b][s], wide[b + 1][s], wide[b + 2][s]};
  c.hi = {wide[b + 3][s], wide[b + 4][s], wide[b + 5][s]};
  return c;
}

uint32_t traceBvhTriangleId(const TraceBvhLayout& layout, size_t slot) {
  uint32_t id;
  std::memcpy(&id, &layout.triangles[3 * slot].w, sizeof id);
  return id;
}

static std::atomic<uint64_t> gTraceBvhBuilds{0};

uint64_t traceBvhBuildCount() { return gTraceBvhBuilds.load(); }

TraceBvh buildTraceBvh(const VulkanContext& ctx, const Scene& scene, uint32_t width) {
  ++gTraceBvhBuilds;
  TraceBvhLayout l = layoutTraceBvh(scene.worldTriangles(), width);
  if (l.triangles.empty()) l.triangles.assign(3, glm::vec4(0.0f));  // no triangle: a leaf of nothing is never read
  TraceBvh b;
  if (width != 2)
    b.nodes = uploadBuffer(ctx, l.wide.data(), l.nodeBytes(), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemClass::Geometry);
  else
    b.nodes = uploadBuffer(ctx, l.nodes.data(), l.nodeBytes(), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemClass::Geometry);
  b.triangles = uploadBuffer(ctx, l.triangles.data(), l.triangles.size() * sizeof(glm::vec4),
                             VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemClass::Geometry);
  b.width = width;
  b.nodeCount = uint32_t(width != 2 ? l.wide.size() / wideNodeVec4s(width) : l.nodes.size());
  b.depth = l.depth;
  b.stack = l.stack;
  b.bytes = l.nodeBytes() + uint64_t(l.triangles.size() * sizeof(glm::vec4));
  b.buildMs = l.buildMs;
  return b;
}

}  // namespace hb
