#include "gpu/primary_bvh.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <vector>

#include "base/errors.h"
#include "base/parallel.h"
#include "gpu/bvh_reinsert.h"

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

// A triangle as the builder moves it: its bounds (empty: a non-finite vertex), centroid (0 for the
// non-finite ones) and index. The builder partitions these in place rather than indices into
// per-triangle arrays, so that every pass over a node reads memory in order.
struct Item {
  Box box;
  glm::vec3 centroid{0.0f};
  uint32_t triangle = 0;
};

struct Builder {
  std::vector<Item>& items;  // shared by the builders of disjoint subtrees
  std::vector<gpu::PrimaryBvhNode> nodes;
  uint32_t depth = 0;

  BvhBuildOptions opt;
  // Per axis its bins' boxes and counts, and the costs of the cuts: sized once (setUp), reused by
  // every partition.
  std::array<std::vector<Box>, 3> bin;
  std::array<std::vector<uint32_t>, 3> binCount;  // all 0 between partitions
  std::array<std::vector<int>, 3> used;           // the bins a partition filled
  std::vector<float> rightCost;

  void setUp(const BvhBuildOptions& o) {
    HB_ASSERT(o.bins >= 2);
    opt = o;
    for (int a = 0; a < 3; ++a) {
      bin[size_t(a)].resize(size_t(o.bins));
      binCount[size_t(a)].assign(size_t(o.bins), 0u);
      used[size_t(a)].reserve(size_t(o.bins));
    }
    rightCost.resize(size_t(o.bins));
  }

  // The bin of centroid coordinate c on an axis whose centroids start at lo, `scale` bins a unit:
  // one formula for binning and for the partition that follows it.
  int binOf(float c, float lo, float scale) const { return std::clamp(int((c - lo) * scale), 0, opt.bins - 1); }

  // Where to cut order[first, first + count): the index of the first right triangle, or 0 for a
  // leaf. Binned SAH (cost 1 a node traversal, 1 a triangle test), opt.bins bins on the centroids'
  // widest extent, or on each axis (opt.allAxes), all binned in one pass over the triangles.
  uint32_t partition(uint32_t first, uint32_t count, const Box& box, const Box& cb) {
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
    }
    for (uint32_t i = first; i < first + count; ++i) {
      const Item& it = items[i];
      for (int axis = 0; axis < 3; ++axis) {
        if (!binned[size_t(axis)]) continue;
        const size_t b = size_t(binOf(it.centroid[axis], cb.lo[axis], scale[axis]));
        if (binCount[size_t(axis)][b]++ == 0) {
          used[size_t(axis)].push_back(int(b));
          bin[size_t(axis)][b] = it.box;
        } else {
          bin[size_t(axis)][b].grow(it.box);
        }
      }
    }
    // The cuts between consecutive non-empty bins: every cut inside a run of empty bins splits the
    // triangles as the one at its end does, at the same cost, and the first of equal costs wins, so
    // sweeping the non-empty bins alone chooses the partition the full sweep of opt.bins does.
    float best = std::numeric_limits<float>::infinity();
    int bestBin = -1, bestAxis = widest;
    for (int axis = 0; axis < 3; ++axis) {
      if (!binned[size_t(axis)]) continue;
      std::vector<int>& u = used[size_t(axis)];
      std::sort(u.begin(), u.end());
      const std::vector<Box>& bx = bin[size_t(axis)];
      std::vector<uint32_t>& n = binCount[size_t(axis)];
      Box acc;
      uint32_t acc_n = 0;
      for (size_t k = u.size(); k-- > 1;) {
        acc.grow(bx[size_t(u[k])]);
        acc_n += n[size_t(u[k])];
        rightCost[k] = acc.halfArea() * float(acc_n);
      }
      Box left;
      uint32_t leftN = 0;
      for (size_t k = 1; k < u.size(); ++k) {
        left.grow(bx[size_t(u[k - 1])]);
        leftN += n[size_t(u[k - 1])];
        const float cost = left.halfArea() * float(leftN) + rightCost[k];
        if (cost < best) {
          best = cost;
          bestBin = u[k];
          bestAxis = axis;
        }
      }
      for (int b : u) n[size_t(b)] = 0;  // the next partition finds its bins empty
      u.clear();
    }
    uint32_t mid = 0;
    const float leafCost = box.halfArea() * float(count);
    if (bestBin > 0 && (count > kPrimaryBvhLeaf || best + box.halfArea() < leafCost)) {
      const auto it = std::partition(items.begin() + first, items.begin() + first + count, [&](const Item& t) {
        return binOf(t.centroid[bestAxis], cb.lo[bestAxis], scale[bestAxis]) < bestBin;
      });
      mid = uint32_t(it - items.begin());
    }
    if (mid == 0 && count > kPrimaryBvhLeaf) {  // no useful SAH cut (equal centroids): the median
      mid = first + count / 2;
      std::nth_element(items.begin() + first, items.begin() + mid, items.begin() + first + count,
                       [&](const Item& a, const Item& b) { return a.centroid[widest] < b.centroid[widest]; });
    }
    return mid;
  }

  // The bounds of items[first, first + count) and where to cut them (0: a leaf), the items
  // partitioned: one step of build().
  uint32_t split(uint32_t first, uint32_t count, Box& box) {
    Box cb;  // the centroids' bounds
    box = Box{};
    for (uint32_t i = first; i < first + count; ++i) {
      box.grow(items[i].box);
      cb.grow(items[i].centroid);
    }
    if (box.empty()) box.lo = box.hi = glm::vec3(0.0f);  // only non-finite triangles: a point
    return count > 1 ? partition(first, count, box, cb) : 0;
  }

  uint32_t build(uint32_t first, uint32_t count, uint32_t level) {
    depth = std::max(depth, level);
    const uint32_t index = uint32_t(nodes.size());
    nodes.emplace_back();
    Box box;
    const uint32_t mid = split(first, count, box);
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

// The top of the tree, split on one thread until it has enough subtrees for every thread; each
// subtree is then built by a Builder of its own (their items are disjoint ranges of one array), and
// the nodes are laid out as the recursive build lays them: a node, its left subtree, its right.
// A split depends only on the items of its range, so the tree is the same bit for bit whatever the
// thread count (HYBRIDBENCH_THREADS=1 is the serial build).
struct TopNode {
  uint32_t first = 0, count = 0, level = 0;
  Box box;
  bool split = false;  // false: a task's subtree (or a leaf split here)
  int left = -1, right = -1;
  int task = -1;  // index into the subtrees built in parallel
};

struct ParallelBuild {
  std::vector<Item>& items;
  const BvhBuildOptions& opt;
  std::vector<TopNode> top;
  std::vector<std::pair<uint32_t, uint32_t>> tasks;  // (first, count) of each subtree; level in top
  std::vector<uint32_t> taskLevel;
  uint32_t maxLevel = 1, minCount = 1;

  int expand(Builder& b, uint32_t first, uint32_t count, uint32_t level) {
    const int index = int(top.size());
    top.push_back({first, count, level});
    if (level >= maxLevel || count < minCount) {
      top[size_t(index)].task = int(tasks.size());
      tasks.emplace_back(first, count);
      taskLevel.push_back(level);
      return index;
    }
    Box box;
    const uint32_t mid = b.split(first, count, box);
    top[size_t(index)].box = box;
    if (mid == 0) return index;  // a leaf
    top[size_t(index)].split = true;
    const int l = expand(b, first, mid - first, level + 1);
    const int r = expand(b, mid, first + count - mid, level + 1);
    top[size_t(index)].left = l;
    top[size_t(index)].right = r;
    return index;
  }

  // Appends top node `i` and what lies under it to `out` in the recursive build's order.
  uint32_t emit(int i, const std::vector<std::vector<gpu::PrimaryBvhNode>>& subtrees,
                std::vector<gpu::PrimaryBvhNode>& out) const {
    const TopNode& t = top[size_t(i)];
    const uint32_t index = uint32_t(out.size());
    if (t.task >= 0) {
      for (gpu::PrimaryBvhNode n : subtrees[size_t(t.task)]) {
        if (n.info.x != 0) n.info.x += index;  // a right child, numbered within its subtree
        out.push_back(n);
      }
      return index;
    }
    out.emplace_back();
    uint32_t right = 0;
    if (t.split) {
      emit(t.left, subtrees, out);
      right = emit(t.right, subtrees, out);
    }
    gpu::PrimaryBvhNode& node = out[index];
    node.lo = glm::vec4(t.box.lo, 0.0f);
    node.hi = glm::vec4(t.box.hi, 0.0f);
    node.info = glm::uvec4(right, t.first, t.count, 0u);
    return index;
  }
};

}  // namespace

PrimaryBvh buildPrimaryBvh(const std::vector<glm::vec3>& vertices, const BvhBuildOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const size_t n = vertices.size() / 3;
  std::vector<Item> items(n);
  for (size_t t = 0; t < n; ++t) {
    Item& item = items[t];
    item.triangle = uint32_t(t);
    const glm::vec3 &v0 = vertices[3 * t], &v1 = vertices[3 * t + 1], &v2 = vertices[3 * t + 2];
    auto finite3 = [](const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
    const bool finite = finite3(v0) && finite3(v1) && finite3(v2);
    if (!finite) continue;
    item.box.grow(v0);
    item.box.grow(v1);
    item.box.grow(v2);
    item.centroid = (item.box.lo + item.box.hi) * 0.5f;
  }
  PrimaryBvh out;
  if (n == 0) {
    gpu::PrimaryBvhNode empty{};
    out.nodes.push_back(empty);  // a leaf with no triangles
    out.depth = 1;
  } else {
    // Subtrees for every thread, four to a thread to even out their sizes; a range under
    // kParallelMinTriangles is not worth a task.
    constexpr uint32_t kParallelMinTriangles = 4096;
    const unsigned threads = analysisThreads();
    ParallelBuild pb{items, options};
    while ((1u << (pb.maxLevel - 1)) < 4 * threads && pb.maxLevel < 16) ++pb.maxLevel;
    pb.minCount = threads > 1 ? kParallelMinTriangles : std::numeric_limits<uint32_t>::max();
    Builder top{items};
    top.setUp(options);
    const int root = pb.expand(top, 0, uint32_t(n), 1);
    std::vector<std::vector<gpu::PrimaryBvhNode>> subtrees(pb.tasks.size());
    std::vector<uint32_t> depths(pb.tasks.size(), 0);
    parallelFor(pb.tasks.size(), [&](size_t k) {
      Builder b{items};
      b.setUp(options);
      b.nodes.reserve(2 * size_t(pb.tasks[k].second));
      b.build(pb.tasks[k].first, pb.tasks[k].second, pb.taskLevel[k]);
      subtrees[k] = std::move(b.nodes);
      depths[k] = b.depth;
    });
    out.nodes.reserve(2 * n);
    pb.emit(root, subtrees, out.nodes);
    out.depth = 0;
    for (const TopNode& t : pb.top) out.depth = std::max(out.depth, t.level);
    for (uint32_t d : depths) out.depth = std::max(out.depth, d);
    out.order.resize(n);
    for (size_t i = 0; i < n; ++i) out.order[i] = items[i].triangle;
    if (options.reinsertRounds > 0) reinsertBvh(out, options.reinsertRounds);
  }
  out.buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace hb
