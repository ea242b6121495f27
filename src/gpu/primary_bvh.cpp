#include "gpu/primary_bvh.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <vector>

#include "base/errors.h"

namespace hb {

namespace {

struct Box {
  glm::vec3 lo{std::numeric_limits<float>::infinity()}, hi{-std::numeric_limits<float>::infinity()};
  void grow(const glm::vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  void grow(const Box& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  bool empty() const { return !(lo.x <= hi.x); }
  // Half the surface area (the SAH's constant factor cancels); 0 for an empty box.
  float halfArea() const {
    if (empty()) return 0.0f;
    const glm::vec3 d = hi - lo;
    return d.x * d.y + d.y * d.z + d.z * d.x;
  }
};

struct Builder {
  std::vector<Box> boxes;            // per triangle (empty: a non-finite vertex)
  std::vector<glm::vec3> centroids;  // per triangle (0 for the non-finite ones)
  std::vector<uint32_t> order;
  std::vector<gpu::PrimaryBvhNode> nodes;
  uint32_t depth = 0;

  BvhBuildOptions opt;
  // Per axis its bins' boxes and counts, and the costs of the cuts: sized once (setUp), reused by
  // every partition.
  std::array<std::vector<Box>, 3> bin;
  std::array<std::vector<uint32_t>, 3> binCount;
  std::vector<float> rightCost;

  void setUp(const BvhBuildOptions& o) {
    HB_ASSERT(o.bins >= 2);
    opt = o;
    for (int a = 0; a < 3; ++a) {
      bin[size_t(a)].resize(size_t(o.bins));
      binCount[size_t(a)].resize(size_t(o.bins));
    }
    rightCost.resize(size_t(o.bins));
  }

  // The bin of centroid coordinate c on an axis whose centroids start at lo, `scale` bins a unit:
  // one formula for binning and for the partition that follows it.
  int binOf(float c, float lo, float scale) const { return std::clamp(int((c - lo) * scale), 0, opt.bins - 1); }

  // Where to cut order[first, first + count): the index of the first right triangle, or 0 for a
  // leaf. Binned SAH (cost 1 a node traversal, 1 a triangle test), opt.bins bins on the centroids'
  // widest extent, or on each axis (opt.allAxes), all binned in one pass over the triangles.
  uint32_t partition(uint32_t first, uint32_t count, const Box& box) {
    Box cb;
    for (uint32_t i = first; i < first + count; ++i) cb.grow(centroids[order[i]]);
    const glm::vec3 ext = cb.hi - cb.lo;
    const int widest = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
    const int bins = opt.bins;
    // The axes binned, and their scales: an axis without extent (or one so thin that bins / extent
    // overflows) has no cut.
    glm::vec3 scale(0.0f);
    std::array<bool, 3> binned{};
    for (int axis = 0; axis < 3; ++axis) {
      if (!opt.allAxes && axis != widest) continue;
      scale[axis] = float(bins) / ext[axis];
      binned[size_t(axis)] = ext[axis] > 0.0f && std::isfinite(scale[axis]);
      if (!binned[size_t(axis)]) continue;
      std::fill(bin[size_t(axis)].begin(), bin[size_t(axis)].end(), Box{});
      std::fill(binCount[size_t(axis)].begin(), binCount[size_t(axis)].end(), 0u);
    }
    for (uint32_t i = first; i < first + count; ++i) {
      const uint32_t t = order[i];
      for (int axis = 0; axis < 3; ++axis) {
        if (!binned[size_t(axis)]) continue;
        const size_t b = size_t(binOf(centroids[t][axis], cb.lo[axis], scale[axis]));
        bin[size_t(axis)][b].grow(boxes[t]);
        ++binCount[size_t(axis)][b];
      }
    }
    float best = std::numeric_limits<float>::infinity();
    int bestBin = -1, bestAxis = widest;
    for (int axis = 0; axis < 3; ++axis) {
      if (!binned[size_t(axis)]) continue;
      const std::vector<Box>& bx = bin[size_t(axis)];
      const std::vector<uint32_t>& n = binCount[size_t(axis)];
      Box acc;
      uint32_t acc_n = 0;
      for (int b = bins - 1; b > 0; --b) {
        acc.grow(bx[size_t(b)]);
        acc_n += n[size_t(b)];
        rightCost[size_t(b)] = acc.halfArea() * float(acc_n);
      }
      Box left;
      uint32_t leftN = 0;
      for (int b = 1; b < bins; ++b) {
        left.grow(bx[size_t(b - 1)]);
        leftN += n[size_t(b - 1)];
        if (leftN == 0 || leftN == count) continue;
        const float cost = left.halfArea() * float(leftN) + rightCost[size_t(b)];
        if (cost < best) {
          best = cost;
          bestBin = b;
          bestAxis = axis;
        }
      }
    }
    uint32_t mid = 0;
    const float leafCost = box.halfArea() * float(count);
    if (bestBin > 0 && (count > kPrimaryBvhLeaf || best + box.halfArea() < leafCost)) {
      const auto it = std::partition(order.begin() + first, order.begin() + first + count, [&](uint32_t t) {
        return binOf(centroids[t][bestAxis], cb.lo[bestAxis], scale[bestAxis]) < bestBin;
      });
      mid = uint32_t(it - order.begin());
    }
    if (mid == 0 && count > kPrimaryBvhLeaf) {  // no useful SAH cut (equal centroids): the median
      mid = first + count / 2;
      std::nth_element(order.begin() + first, order.begin() + mid, order.begin() + first + count,
                       [&](uint32_t a, uint32_t b) { return centroids[a][widest] < centroids[b][widest]; });
    }
    return mid;
  }

  uint32_t build(uint32_t first, uint32_t count, uint32_t level) {
    depth = std::max(depth, level);
    const uint32_t index = uint32_t(nodes.size());
    nodes.emplace_back();
    Box box;
    for (uint32_t i = first; i < first + count; ++i) box.grow(boxes[order[i]]);
    if (box.empty()) box.lo = box.hi = glm::vec3(0.0f);  // only non-finite triangles: a point
    const uint32_t mid = count > 1 ? partition(first, count, box) : 0;
    uint32_t right = 0;
    if (mid != 0) {
      build(first, mid - first, level + 1);
      right = build(mid, first + count - mid, level + 1);
    }
    gpu::PrimaryBvhNode& node = nodes[index];
    node.lo = glm::vec4(box.lo, 0.0f);
    node.hi = glm::vec4(box.hi, 0.0f);
    node.info = glm::uvec4(right, first, count, 0u);
    return index;
  }
};

}  // namespace

PrimaryBvh buildPrimaryBvh(const std::vector<glm::vec3>& vertices, const BvhBuildOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  Builder b;
  b.setUp(options);
  const size_t n = vertices.size() / 3;
  b.boxes.resize(n);
  b.centroids.assign(n, glm::vec3(0.0f));
  b.order.resize(n);
  for (size_t t = 0; t < n; ++t) {
    b.order[t] = uint32_t(t);
    const glm::vec3 &v0 = vertices[3 * t], &v1 = vertices[3 * t + 1], &v2 = vertices[3 * t + 2];
    auto finite3 = [](const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
    const bool finite = finite3(v0) && finite3(v1) && finite3(v2);
    if (!finite) continue;
    b.boxes[t].grow(v0);
    b.boxes[t].grow(v1);
    b.boxes[t].grow(v2);
    b.centroids[t] = (b.boxes[t].lo + b.boxes[t].hi) * 0.5f;
  }
  PrimaryBvh out;
  if (n == 0) {
    gpu::PrimaryBvhNode empty{};
    out.nodes.push_back(empty);  // a leaf with no triangles
    out.depth = 1;
  } else {
    b.nodes.reserve(2 * n);
    b.build(0, uint32_t(n), 1);
    out.nodes = std::move(b.nodes);
    out.order = std::move(b.order);
    out.depth = b.depth;
  }
  out.buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace hb
