#include "reference/bvh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "base/errors.h"

namespace hb {

constexpr double kEps = std::numeric_limits<double>::epsilon();

bool isDegenerate(const BvhTriangle& tri) {
  const glm::dvec3 e1 = tri.v1 - tri.v0, e2 = tri.v2 - tri.v0;
  const double s = glm::dot(e1 + e2, e1 + e2) + glm::dot(tri.v0, tri.v0);
  if (!std::isfinite(s)) return true;
  return glm::length(glm::cross(e1, e2)) <= 8.0 * kEps * glm::length(e1) * glm::length(e2);
}

// Edge function in extended precision, used only when the double one is exactly 0 (paper, 4.3:
// recompute in higher precision). a*b - c*d with the operands swapped gives exactly the negated
// value (round-to-nearest is sign-symmetric), so two triangles sharing an edge still agree.
static double edgeFunctionExtended(double a, double b, double c, double d) {
  return double((long double)a * (long double)b - (long double)c * (long double)d);
}

bool intersectTriangleWatertight(const BvhTriangle& tri, const glm::dvec3& org, const glm::dvec3& dir, double tMin,
                                 double tMax, double& tOut) {
  if (isDegenerate(tri)) return false;  // det could be a tiny non-zero rounding residue
  // 1. Permute so that z is the ray's largest-magnitude axis; swap x/y to keep the winding.
  const glm::dvec3 ad = glm::abs(dir);
  const int kz = ad.x > ad.y ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
  int kx = (kz + 1) % 3, ky = (kx + 1) % 3;
  if (dir[kz] < 0.0) std::swap(kx, ky);
  if (!(dir[kz] != 0.0)) return false;  // zero or NaN direction
  // 2. Shear so that the ray becomes the +z axis through the origin.
  const double sx = dir[kx] / dir[kz], sy = dir[ky] / dir[kz], sz = 1.0 / dir[kz];
  const glm::dvec3 a = tri.v0 - org, b = tri.v1 - org, c = tri.v2 - org;
  const double ax = a[kx] - sx * a[kz], ay = a[ky] - sy * a[kz];
  const double bx = b[kx] - sx * b[kz], by = b[ky] - sy * b[kz];
  const double cx = c[kx] - sx * c[kz], cy = c[ky] - sy * c[kz];
  // 3. 2D edge functions: scaled barycentrics of the ray's (0, 0).
  double u = cx * by - cy * bx;
  double v = ax * cy - ay * cx;
  double w = bx * ay - by * ax;
  if (u == 0.0 || v == 0.0 || w == 0.0) {
    u = edgeFunctionExtended(cx, by, cy, bx);
    v = edgeFunctionExtended(ax, cy, ay, cx);
    w = edgeFunctionExtended(bx, ay, by, ax);
  }
  // 4. Outside unless all share a sign (zeros allowed: edges and vertices hit; both faces).
  if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) return false;
  const double det = u + v + w;
  if (det == 0.0 || !std::isfinite(det)) return false;  // degenerate, or the ray in its plane
  // 5. Scaled hit distance; t = T / det.
  const double tScaled = u * (sz * a[kz]) + v * (sz * b[kz]) + w * (sz * c[kz]);
  const double t = tScaled / det;
  if (!(t >= tMin && t <= tMax)) return false;  // also rejects NaN
  tOut = t;
  return true;
}

Bvh::Bvh(std::vector<BvhTriangle> triangles) : inputs_(std::move(triangles)) {
  triangles_.reserve(inputs_.size());
  for (size_t i = 0; i < inputs_.size(); ++i) {
    if (isDegenerate(inputs_[i])) {
      ++dropped_;
    } else {
      triangles_.push_back(inputs_[i]);
      ids_.push_back(uint32_t(i));
    }
  }
  if (triangles_.empty()) return;
  std::vector<glm::dvec3> centroids(triangles_.size());
  for (size_t i = 0; i < triangles_.size(); ++i)
    centroids[i] = (triangles_[i].v0 + triangles_[i].v1 + triangles_[i].v2) / 3.0;
  nodes_.reserve(2 * triangles_.size());
  build(0, uint32_t(triangles_.size()), centroids);
}

uint32_t Bvh::build(uint32_t first, uint32_t count, std::vector<glm::dvec3>& centroids) {
  const uint32_t index = uint32_t(nodes_.size());
  nodes_.push_back({});
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  glm::dvec3 clo = lo, chi = hi;
  for (uint32_t i = first; i < first + count; ++i) {
    const auto& t = triangles_[i];
    lo = glm::min(lo, glm::min(t.v0, glm::min(t.v1, t.v2)));
    hi = glm::max(hi, glm::max(t.v0, glm::max(t.v1, t.v2)));
    clo = glm::min(clo, centroids[i]);
    chi = glm::max(chi, centroids[i]);
  }
  nodes_[index].lo = lo;
  nodes_[index].hi = hi;
  const glm::dvec3 extent = chi - clo;
  const int axis = extent.x > extent.y ? (extent.x > extent.z ? 0 : 2) : (extent.y > extent.z ? 1 : 2);
  if (count <= 4 || extent[axis] <= 0.0) {
    nodes_[index].firstOrRight = first;
    nodes_[index].count = count;
    return index;
  }
  // Median split: sort a permutation of [first, first+count) by centroid, then apply it.
  std::vector<uint32_t> order(count);
  for (uint32_t i = 0; i < count; ++i) order[i] = first + i;
  const uint32_t half = count / 2;
  std::nth_element(order.begin(), order.begin() + half, order.end(),
                   [&](uint32_t p, uint32_t q) { return centroids[p][axis] < centroids[q][axis]; });
  std::vector<BvhTriangle> tris(count);
  std::vector<glm::dvec3> cents(count);
  std::vector<uint32_t> ids(count);
  for (uint32_t i = 0; i < count; ++i)
    tris[i] = triangles_[order[i]], cents[i] = centroids[order[i]], ids[i] = ids_[order[i]];
  std::copy(tris.begin(), tris.end(), triangles_.begin() + first);
  std::copy(cents.begin(), cents.end(), centroids.begin() + first);
  std::copy(ids.begin(), ids.end(), ids_.begin() + first);
  build(first, half, centroids);
  const uint32_t right = build(first + half, count - half, centroids);
  nodes_[index].firstOrRight = right;
  nodes_[index].count = 0;
  return index;
}

// Slab test, widened by (1 + 2γ3) on the far side (pbrt-v4, Bounds3::IntersectP) so that the box
// test cannot reject a ray that the watertight triangle test would hit. Zero direction
// components are handled explicitly (0 * inf = NaN otherwise).
static bool rayHitsBox(const glm::dvec3& lo, const glm::dvec3& hi, const glm::dvec3& org, const glm::dvec3& invDir,
                       const glm::dvec3& dir, double tMin, double tMax) {
  constexpr double kGamma3 = 3.0 * kEps / (1.0 - 3.0 * kEps);
  double t0 = tMin, t1 = tMax;
  for (int i = 0; i < 3; ++i) {
    if (dir[i] == 0.0) {
      if (org[i] < lo[i] || org[i] > hi[i]) return false;
      continue;
    }
    double tNear = (lo[i] - org[i]) * invDir[i];
    double tFar = (hi[i] - org[i]) * invDir[i];
    if (tNear > tFar) std::swap(tNear, tFar);
    tFar *= 1.0 + 2.0 * kGamma3;
    t0 = std::max(t0, tNear);
    t1 = std::min(t1, tFar);
    if (t0 > t1) return false;
  }
  return true;
}

template <class OnTriangle>
void Bvh::walk(const glm::dvec3& org, const glm::dvec3& dir, double tMin, const double& tFar,
               OnTriangle onTriangle) const {
  if (nodes_.empty() || !(glm::dot(dir, dir) > 0.0) || !(tMin <= tFar)) return;
  const glm::dvec3 invDir = 1.0 / dir;
  uint32_t stack[128];  // depth of a median-split tree ≤ log2(n) + 1
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    if (!rayHitsBox(n.lo, n.hi, org, invDir, dir, tMin, tFar)) continue;
    if (n.count > 0) {
      for (uint32_t i = n.firstOrRight; i < n.firstOrRight + n.count; ++i)
        if (!onTriangle(i)) return;
    } else {
      HB_ASSERT(top + 2 <= 128);
      stack[top++] = n.firstOrRight;
      stack[top++] = uint32_t(&n - nodes_.data()) + 1;
    }
  }
}

template <bool AnyHit>
bool Bvh::traverse(const glm::dvec3& org, const glm::dvec3& dir, double tMin, double tMax, double& t,
                   uint32_t& triangle) const {
  bool hit = false;
  double closest = tMax;  // shortened by each hit, so the walk prunes boxes beyond it
  walk(org, dir, tMin, closest, [&](uint32_t i) {
    double ti;
    if (!intersectTriangleWatertight(triangles_[i], org, dir, tMin, closest, ti)) return true;
    hit = true;
    closest = ti;
    triangle = ids_[i];
    return !AnyHit;
  });
  if (hit) t = closest;
  return hit;
}

bool Bvh::occluded(const glm::dvec3& origin, const glm::dvec3& dir, double tMin, double tMax) const {
  double t;
  uint32_t triangle;
  return traverse<true>(origin, dir, tMin, tMax, t, triangle);
}

bool Bvh::closestHit(const glm::dvec3& origin, const glm::dvec3& dir, double tMin, double tMax, double& t) const {
  uint32_t triangle;
  return traverse<false>(origin, dir, tMin, tMax, t, triangle);
}

bool Bvh::closestHit(const glm::dvec3& origin, const glm::dvec3& dir, double tMin, double tMax, double& t,
                     uint32_t& triangle) const {
  return traverse<false>(origin, dir, tMin, tMax, t, triangle);
}

void Bvh::allHits(const glm::dvec3& org, const glm::dvec3& dir, double tMin, double tMax,
                  std::vector<BvhHit>& hits) const {
  hits.clear();
  walk(org, dir, tMin, tMax, [&](uint32_t i) {
    double t;
    if (intersectTriangleWatertight(triangles_[i], org, dir, tMin, tMax, t)) hits.push_back({t, ids_[i]});
    return true;
  });
  std::sort(hits.begin(), hits.end(),
            [](const BvhHit& a, const BvhHit& b) { return a.t < b.t || (a.t == b.t && a.triangle < b.triangle); });
}

Bvh buildBvh(const Scene& scene) {
  std::vector<BvhTriangle> tris;
  tris.reserve(scene.triangleCount());
  for (const auto& inst : scene.instances) {
    HB_ASSERT(inst.mesh < scene.meshes.size());
    const glm::dmat4 m(inst.transform);
    for (const auto& prim : scene.meshes[inst.mesh].primitives) {
      HB_ASSERT(uint64_t(prim.firstIndex) + prim.indexCount <= scene.indices.size());
      auto world = [&](uint32_t k) {
        const uint64_t v = uint64_t(prim.vertexOffset) + scene.indices[prim.firstIndex + k];
        HB_ASSERT(v < scene.vertices.size());
        return glm::dvec3(m * glm::dvec4(glm::dvec3(scene.vertices[v].position), 1.0));
      };
      for (uint32_t k = 0; k + 2 < prim.indexCount; k += 3) tris.push_back({world(k), world(k + 1), world(k + 2)});
    }
  }
  return Bvh(std::move(tris));
}

}  // namespace hb
