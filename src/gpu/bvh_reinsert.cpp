#include "gpu/bvh_reinsert.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <vector>

#include "base/errors.h"

namespace hb {

namespace {

// The tree with parent links, as reinsertion edits it: a leaf keeps its range of the old order.
struct Node {
  glm::vec3 lo{0.0f}, hi{0.0f};
  int parent = -1, left = -1, right = -1;  // left < 0: a leaf
  uint32_t first = 0, count = 0;           // a leaf's triangles: order[first, first + count)
  bool leaf() const { return left < 0; }
};

double halfArea(const glm::vec3& lo, const glm::vec3& hi) {
  const glm::dvec3 d = glm::max(glm::dvec3(hi) - glm::dvec3(lo), glm::dvec3(0.0));
  return d.x * d.y + d.y * d.z + d.z * d.x;
}
double halfArea(const Node& n) { return halfArea(n.lo, n.hi); }
double unionArea(const Node& a, const Node& b) { return halfArea(glm::min(a.lo, b.lo), glm::max(a.hi, b.hi)); }

struct Tree {
  std::vector<Node> n;
  int root = 0;

  double cost() const {
    double c = 0.0;
    for (const Node& x : n) c += halfArea(x) * (x.leaf() ? double(x.count) : 1.0);
    const double r = halfArea(n[size_t(root)]);
    return r > 0.0 ? c / r : c;
  }

  void replaceChild(int parent, int from, int to) {
    if (parent < 0) {
      root = to;
    } else {
      Node& p = n[size_t(parent)];
      (p.left == from ? p.left : p.right) = to;
    }
    n[size_t(to)].parent = parent;
  }

  // The boxes from node i up to the root, each the union of its children's (exact: float min and max).
  void refit(int i) {
    for (; i >= 0; i = n[size_t(i)].parent) {
      Node& x = n[size_t(i)];
      const Node &l = n[size_t(x.left)], &r = n[size_t(x.right)];
      x.lo = glm::min(l.lo, r.lo);
      x.hi = glm::max(l.hi, r.hi);
    }
  }

  // Where node x adds the least area beside an existing node b (the tree without x): branch and
  // bound from the root. Placing x beside b adds A(b ∪ x) for the new parent and, for each ancestor
  // a of b, A(a ∪ x) − A(a).
  int bestSibling(int x) const {
    const Node& xn = n[size_t(x)];
    const double ax = halfArea(xn);
    struct Entry {
      double bound, inherited;
      int node;
      bool operator<(const Entry& o) const { return bound != o.bound ? bound > o.bound : node > o.node; }
    };
    std::priority_queue<Entry> queue;
    queue.push({ax, 0.0, root});
    double best = std::numeric_limits<double>::infinity();
    int bestNode = root;
    while (!queue.empty()) {
      const Entry e = queue.top();
      queue.pop();
      if (e.bound >= best) break;
      const Node& b = n[size_t(e.node)];
      const double direct = unionArea(b, xn);
      const double total = e.inherited + direct;
      if (total < best) {
        best = total;
        bestNode = e.node;
      }
      if (!b.leaf()) {
        const double inherited = total - halfArea(b);
        if (inherited + ax < best) {
          queue.push({inherited + ax, inherited, b.left});
          queue.push({inherited + ax, inherited, b.right});
        }
      }
    }
    return bestNode;
  }

  // Puts node x beside its best sibling, with free node f as their parent.
  void insert(int x, int f) {
    const int b = bestSibling(x);
    Node& fn = n[size_t(f)];
    const int parent = n[size_t(b)].parent;
    replaceChild(parent, b, f);
    fn.left = b;
    fn.right = x;
    n[size_t(b)].parent = f;
    n[size_t(x)].parent = f;
    refit(f);
  }

  // Takes interior node i (not the root) out, its sibling taking its parent's place, and puts its
  // two children back, the larger first, in the nodes i and its parent freed.
  void reinsert(int i) {
    const int p = n[size_t(i)].parent, l = n[size_t(i)].left, r = n[size_t(i)].right;
    const Node& pn = n[size_t(p)];
    const int sibling = pn.left == i ? pn.right : pn.left;
    const int grand = pn.parent;
    replaceChild(grand, p, sibling);
    if (grand >= 0) refit(grand);
    const bool lFirst = halfArea(n[size_t(l)]) >= halfArea(n[size_t(r)]);
    insert(lFirst ? l : r, i);
    insert(lFirst ? r : l, p);
  }
};

Tree fromPrimary(const PrimaryBvh& t) {
  Tree out;
  out.n.resize(t.nodes.size());
  for (size_t i = 0; i < t.nodes.size(); ++i) {
    const gpu::PrimaryBvhNode& s = t.nodes[i];
    Node& d = out.n[i];
    d.lo = glm::vec3(s.lo);
    d.hi = glm::vec3(s.hi);
    if (s.info.x != 0) {
      d.left = int(i + 1);
      d.right = int(s.info.x);
      out.n[i + 1].parent = int(i);
      out.n[s.info.x].parent = int(i);
    } else {
      d.first = s.info.y;
      d.count = s.info.z;
    }
  }
  return out;
}

// Lays the tree out depth first (a node, its left subtree, its right), the leaves' triangles in
// that order.
void toPrimary(const Tree& t, PrimaryBvh& out) {
  std::vector<gpu::PrimaryBvhNode> nodes;
  std::vector<uint32_t> order;
  nodes.reserve(t.n.size());
  order.reserve(out.order.size());
  uint32_t depth = 0;
  const std::function<uint32_t(int, uint32_t)> emit = [&](int i, uint32_t level) -> uint32_t {
    depth = std::max(depth, level);
    const Node& x = t.n[size_t(i)];
    const uint32_t index = uint32_t(nodes.size());
    nodes.emplace_back();
    const uint32_t first = uint32_t(order.size());
    uint32_t right = 0;
    if (x.leaf()) {
      for (uint32_t k = 0; k < x.count; ++k) order.push_back(out.order[x.first + k]);
    } else {
      emit(x.left, level + 1);
      right = emit(x.right, level + 1);
    }
    gpu::PrimaryBvhNode& d = nodes[index];
    d.lo = glm::vec4(x.lo, 0.0f);
    d.hi = glm::vec4(x.hi, 0.0f);
    d.info = glm::uvec4(right, first, uint32_t(order.size()) - first, 0u);
    return index;
  };
  emit(t.root, 1);
  HB_ASSERT(order.size() == out.order.size() && nodes.size() == out.nodes.size());
  out.nodes = std::move(nodes);
  out.order = std::move(order);
  out.depth = depth;
}

}  // namespace

double bvhSahCost(const PrimaryBvh& tree) { return tree.nodes.empty() ? 0.0 : fromPrimary(tree).cost(); }

BvhReinsertStats reinsertBvh(PrimaryBvh& tree, uint32_t maxRounds) {
  BvhReinsertStats s;
  s.depthBefore = s.depthAfter = tree.depth;
  if (tree.nodes.size() < 7 || maxRounds == 0) {
    s.costBefore = s.costAfter = bvhSahCost(tree);
    return s;
  }
  Tree t = fromPrimary(tree);
  s.costBefore = t.cost();
  double cost = s.costBefore;
  std::vector<std::pair<double, int>> picked;
  std::vector<uint8_t> tried(t.n.size(), 0);
  for (; s.rounds < maxRounds;) {
    picked.clear();
    for (size_t i = 0; i < t.n.size(); ++i) {
      const Node& x = t.n[i];
      if (x.leaf() || int(i) == t.root || x.parent == t.root || tried[i]) continue;
      const double a = halfArea(x), al = halfArea(t.n[size_t(x.left)]), ar = halfArea(t.n[size_t(x.right)]);
      const double lo = std::max(std::min(al, ar), 1e-30), mean = std::max(0.5 * (al + ar), 1e-30);
      picked.emplace_back(a * (a / mean) * (a / lo), int(i));
    }
    if (picked.empty()) break;  // e.g. a tree of the root, its two children and their leaves
    const size_t k = std::max<size_t>(1, picked.size() / 100);
    std::partial_sort(picked.begin(), picked.begin() + ptrdiff_t(k), picked.end(), [](const auto& a, const auto& b) {
      return a.first != b.first ? a.first > b.first : a.second < b.second;
    });
    for (size_t j = 0; j < k; ++j) {
      const int i = picked[j].second;
      const Node& x = t.n[size_t(i)];
      tried[size_t(i)] = 1;
      if (x.leaf() || i == t.root || x.parent < 0 || x.parent == t.root) continue;
      t.reinsert(i);
      ++s.reinserted;
    }
    ++s.rounds;
    const double now = t.cost();
    const bool small = now > cost * (1.0 - 1e-4);
    cost = now;
    if (small) break;
  }
  toPrimary(t, tree);
  s.costAfter = bvhSahCost(tree);  // summed in the new layout's order, as a caller would
  s.depthAfter = tree.depth;
  return s;
}

}  // namespace hb
