#include "gpu/trace_bvh.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <vector>

#include "base/errors.h"
#include "gpu/primary_bvh.h"

namespace hb {

namespace {

float halfAreaOf(const gpu::PrimaryBvhNode& n) {
  const glm::vec3 d = glm::max(glm::vec3(n.hi) - glm::vec3(n.lo), glm::vec3(0.0f));
  return d.x * d.y + d.y * d.z + d.z * d.x;
}

// Collapses the binary tree below binary node `b` into wide nodes, depth first (a node before its
// children); returns the wide node's index.
struct WideCollapse {
  const std::vector<gpu::PrimaryBvhNode>& binary;
  std::vector<glm::vec4>& out;
  uint32_t width;
  uint32_t depth = 0;

  uint32_t build(uint32_t b, uint32_t level) {
    std::vector<uint32_t> kids;
    if (binary[b].info.x == 0)
      kids = {b};  // the root is a leaf: one child
    else
      kids = {b + 1, binary[b].info.x};
    while (kids.size() < width) {
      int widest = -1;
      float area = -1.0f;
      for (size_t i = 0; i < kids.size(); ++i)
        if (binary[kids[i]].info.x != 0 && halfAreaOf(binary[kids[i]]) > area) {
          area = halfAreaOf(binary[kids[i]]);
          widest = int(i);
        }
      if (widest < 0) break;
      const uint32_t k = kids[size_t(widest)];
      kids[size_t(widest)] = k + 1;  // its children take its place, in order
      kids.insert(kids.begin() + widest + 1, binary[k].info.x);
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
      if (k.info.x == 0) {
        HB_ASSERT(k.info.z >= 1 && k.info.z <= 8 && k.info.y < (1u << 28));
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
      WideCollapse c{out.nodes, out.wide, width};
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
