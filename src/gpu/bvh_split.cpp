#include "gpu/bvh_split.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <utility>
#include <vector>

namespace hb {

namespace {

bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

double halfArea(const TriangleReference& r) {
  const glm::dvec3 d = glm::max(glm::dvec3(r.hi) - glm::dvec3(r.lo), glm::dvec3(0.0));
  return d.x * d.y + d.y * d.z + d.z * d.x;
}
// The reference's priority: its box's half area; with `excessOnly`, less what the triangle's
// own pieces would keep of it (its projected areas, scaled to the reference's share of its box), so
// that a triangle in an axis plane, whose pieces' boxes are as large as it, is not split first.
double priority(const TriangleReference& r, const std::vector<glm::vec3>& v, bool excessOnly) {
  if (!excessOnly) return halfArea(r);
  const glm::dvec3 a(v[3 * size_t(r.triangle)]), b(v[3 * size_t(r.triangle) + 1]), c(v[3 * size_t(r.triangle) + 2]);
  const glm::dvec3 n = glm::cross(b - a, c - a);
  const double own = 0.5 * (std::abs(n.x) + std::abs(n.y) + std::abs(n.z));
  const glm::dvec3 e = glm::max(a, glm::max(b, c)) - glm::min(a, glm::min(b, c));
  const double full = e.x * e.y + e.y * e.z + e.z * e.x;
  return halfArea(r) - 2.0 * own * (full > 0.0 ? halfArea(r) / full : 0.0);
}

// The largest float ≤ x and the smallest float ≥ x, one float step further out: the double that is
// rounded carries the clipping's own rounding (far below a float step), so one step out holds it.
float floatBelow(double x) {
  float f = float(x);
  if (double(f) > x) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return std::nextafter(f, -std::numeric_limits<float>::infinity());
}
float floatAbove(double x) {
  float f = float(x);
  if (double(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return std::nextafter(f, std::numeric_limits<float>::infinity());
}

using Polygon = std::vector<glm::dvec3>;

// Sutherland–Hodgman: the part of `poly` with coordinate `axis` ≤ v (keepBelow) or ≥ v.
void clip(const Polygon& poly, int axis, double v, bool keepBelow, Polygon& out) {
  out.clear();
  const size_t n = poly.size();
  for (size_t i = 0; i < n; ++i) {
    const glm::dvec3& p = poly[i];
    const glm::dvec3& q = poly[(i + 1) % n];
    const bool inP = keepBelow ? p[axis] <= v : p[axis] >= v;
    const bool inQ = keepBelow ? q[axis] <= v : q[axis] >= v;
    if (inP) out.push_back(p);
    if (inP != inQ) {
      const double t = (v - p[axis]) / (q[axis] - p[axis]);
      glm::dvec3 x = p + t * (q - p);
      x[axis] = v;
      out.push_back(x);
    }
  }
}

// The box of triangle `tri`'s part inside [lo, hi], as a reference: clipped in double to the box
// widened by `slack` on every side (so that rounding in the clip cannot lose a sliver of the part
// that touches the box), rounded outward to float, then clamped to [lo, hi] itself (exact: the part
// lies inside it). False when the part is empty.
bool clippedBox(const glm::dvec3 tri[3], const glm::vec3& lo, const glm::vec3& hi, double slack, TriangleReference& out,
                Polygon& a, Polygon& b) {
  a.assign(tri, tri + 3);
  for (int axis = 0; axis < 3 && !a.empty(); ++axis) {
    clip(a, axis, double(lo[axis]) - slack, false, b);
    clip(b, axis, double(hi[axis]) + slack, true, a);
  }
  if (a.size() < 3) return false;
  glm::dvec3 area(0.0);  // Newell: twice the polygon's vector area
  for (size_t i = 0; i < a.size(); ++i) area += glm::cross(a[i], a[(i + 1) % a.size()]);
  const glm::dvec3 full = glm::cross(tri[1] - tri[0], tri[2] - tri[0]);
  if (glm::length(area) <= 1e-9 * glm::length(full)) return false;
  glm::dvec3 plo(std::numeric_limits<double>::infinity()), phi(-std::numeric_limits<double>::infinity());
  for (const glm::dvec3& p : a) {
    plo = glm::min(plo, p);
    phi = glm::max(phi, p);
  }
  for (int axis = 0; axis < 3; ++axis) {
    out.lo[axis] = std::max(floatBelow(plo[axis]), lo[axis]);
    out.hi[axis] = std::min(floatAbove(phi[axis]), hi[axis]);
    if (out.lo[axis] > out.hi[axis]) return false;  // the part lies in the slack only
  }
  return true;
}

// The plane of the coarsest level of the dyadic grid over [sceneLo, sceneLo + extent] strictly
// inside (lo, hi), as a float; NaN where none is (a box a float step wide).
float dyadicPlane(float lo, float hi, float sceneLo, double extent) {
  if (!(extent > 0.0) || !(hi > lo)) return std::numeric_limits<float>::quiet_NaN();
  const double ulo = (double(lo) - sceneLo) / extent, uhi = (double(hi) - sceneLo) / extent;
  for (int level = 1; level <= 40; ++level) {
    const double step = std::ldexp(1.0, -level);
    const double k = std::floor(ulo / step) + 1.0;
    if (k * step >= uhi) continue;
    const float plane = float(double(sceneLo) + k * step * extent);
    if (plane > lo && plane < hi) return plane;
  }
  return std::numeric_limits<float>::quiet_NaN();
}

}  // namespace

std::vector<TriangleReference> splitTriangleReferences(const std::vector<glm::vec3>& vertices, double budget,
                                                       bool excessOnly, TriangleSplitStats* stats) {
  const size_t n = vertices.size() / 3;
  std::vector<TriangleReference> refs(n);
  glm::vec3 sceneLo(std::numeric_limits<float>::infinity()), sceneHi(-std::numeric_limits<float>::infinity());
  for (size_t t = 0; t < n; ++t) {
    TriangleReference& r = refs[t];
    r.triangle = uint32_t(t);
    const glm::vec3 &v0 = vertices[3 * t], &v1 = vertices[3 * t + 1], &v2 = vertices[3 * t + 2];
    if (!(finite3(v0) && finite3(v1) && finite3(v2))) {
      r.lo = glm::vec3(std::numeric_limits<float>::infinity());
      r.hi = glm::vec3(-std::numeric_limits<float>::infinity());
      continue;
    }
    r.lo = glm::min(v0, glm::min(v1, v2));
    r.hi = glm::max(v0, glm::max(v1, v2));
    sceneLo = glm::min(sceneLo, r.lo);
    sceneHi = glm::max(sceneHi, r.hi);
  }
  TriangleSplitStats s;
  const uint64_t allowed = budget > 0.0 ? uint64_t(std::floor(budget * double(n))) : 0;
  if (allowed == 0 || !(sceneLo.x <= sceneHi.x)) {
    if (stats) *stats = s;
    return refs;
  }
  const glm::dvec3 extent = glm::dvec3(sceneHi) - glm::dvec3(sceneLo);
  const double slack = 1e-9 * std::max(extent.x, std::max(extent.y, extent.z));

  // The largest box first; the lower index first among equal areas (a max-heap on (area, −index)).
  using Entry = std::pair<double, uint32_t>;
  auto lower = [](const Entry& a, const Entry& b) {
    return a.first < b.first || (a.first == b.first && a.second > b.second);
  };
  std::priority_queue<Entry, std::vector<Entry>, decltype(lower)> heap(lower);
  for (uint32_t i = 0; i < n; ++i)
    if (refs[i].lo.x <= refs[i].hi.x) heap.push({priority(refs[i], vertices, excessOnly), i});

  Polygon pa, pb;
  // A reference whose triangle misses one side shrinks without a split; bound those steps too.
  uint64_t steps = 0;
  const uint64_t maxSteps = 8 * allowed + n;
  while (s.splits < allowed && !heap.empty() && steps++ < maxSteps) {
    const uint32_t i = heap.top().second;
    heap.pop();
    const TriangleReference r = refs[i];
    const uint32_t t = r.triangle;
    const glm::dvec3 tri[3] = {glm::dvec3(vertices[3 * size_t(t)]), glm::dvec3(vertices[3 * size_t(t) + 1]),
                               glm::dvec3(vertices[3 * size_t(t) + 2])};
    // The axes from the box's longest to its shortest; the first with a grid plane inside the box.
    int axes[3] = {0, 1, 2};
    const glm::vec3 d = r.hi - r.lo;
    std::stable_sort(axes, axes + 3, [&](int a, int b) { return d[a] > d[b]; });
    int axis = -1;
    float plane = 0.0f;
    for (int a : axes) {
      plane = dyadicPlane(r.lo[a], r.hi[a], sceneLo[a], extent[a]);
      if (!std::isnan(plane)) {
        axis = a;
        break;
      }
    }
    if (axis < 0) continue;  // too thin to split: it leaves the heap
    glm::vec3 leftHi = r.hi, rightLo = r.lo;
    leftHi[axis] = plane;
    rightLo[axis] = plane;
    TriangleReference left{}, right{};
    left.triangle = right.triangle = t;
    const bool hasLeft = clippedBox(tri, r.lo, leftHi, slack, left, pa, pb);
    const bool hasRight = clippedBox(tri, rightLo, r.hi, slack, right, pa, pb);
    if (hasLeft && hasRight) {
      refs[i] = left;
      refs.push_back(right);
      heap.push({priority(left, vertices, excessOnly), i});
      heap.push({priority(right, vertices, excessOnly), uint32_t(refs.size() - 1)});
      ++s.splits;
    } else if (hasLeft || hasRight) {
      refs[i] = hasLeft ? left : right;
      heap.push({priority(refs[i], vertices, excessOnly), i});
      ++s.shrunk;
    }
    // Neither side: only rounding can say so (the box held a part); keep the reference as it was.
  }
  if (stats) *stats = s;
  return refs;
}

}  // namespace hb
