#include "reference/cull_ref.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "base/errors.h"

namespace hb {

TileRect tileRect(uint32_t tx, uint32_t ty, uint32_t tileSize, uint32_t width, uint32_t height) {
  HB_ASSERT(tileSize > 0 && tx * tileSize < width && ty * tileSize < height);
  const uint32_t x0 = tx * tileSize;
  const uint32_t y0 = ty * tileSize;
  return {x0, y0, std::min(x0 + tileSize, width), std::min(y0 + tileSize, height)};
}

uint32_t tileCount(uint32_t pixels, uint32_t tileSize) { return (pixels + tileSize - 1) / tileSize; }

template <typename T>
std::array<glm::vec<3, T>, 4> tileCornerRays(const ProjectionParams<T>& proj, const TileRect& rect, uint32_t width,
                                             uint32_t height) {
  // ndc = 2*(px/W) - 1: the product by 2 is exact, so an fma and a separate multiply-add agree.
  auto ray = [&](uint32_t px, uint32_t py) {
    const T ndcX = T(2) * (T(px) / T(width)) - T(1);
    const T ndcY = T(2) * (T(py) / T(height)) - T(1);
    // Inverse projection on the plane z = -1 (thesis eq. 4.3 with w dropped).
    return glm::vec<3, T>(ndcX / proj.a, ndcY / proj.b, T(-1));
  };
  return {ray(rect.x0, rect.y0), ray(rect.x1, rect.y0), ray(rect.x1, rect.y1), ray(rect.x0, rect.y1)};
}

template <typename T>
static Plane<T> planeThroughEye(const glm::vec<3, T>& p, const glm::vec<3, T>& q) {
  const glm::vec<3, T> c = glm::cross(p, q);
  return {c / std::sqrt(glm::dot(c, c)), T(0)};
}

template <typename T>
std::array<Plane<T>, 4> tileSidePlanes(const std::array<glm::vec<3, T>, 4>& r) {
  // With A > 0, B < 0: r0 = (xl, yt, -1), r1 = (xr, yt, -1) etc. with xl < xr, yb < yt;
  // cross(r3, r0) = (yt-yb)·(1, 0, xl): x + xl*z >= 0 ⇔ x/(-z) >= xl, the inside. Likewise top
  // ∝ (0, -1, -yt), right ∝ (-1, 0, -xr), bottom ∝ (0, 1, yb).
  return {planeThroughEye(r[3], r[0]), planeThroughEye(r[0], r[1]), planeThroughEye(r[1], r[2]),
          planeThroughEye(r[2], r[3])};
}

template <typename T>
T viewZFromDepth(T depth, const ProjectionParams<T>& proj) {
  return -proj.d / (depth + proj.c);
}

TileDepthRange tileDepthRange(const std::vector<float>& depth, uint32_t width, uint32_t height, const TileRect& rect) {
  HB_ASSERT(depth.size() == size_t(width) * height && rect.x1 <= width && rect.y1 <= height);
  TileDepthRange range;
  for (uint32_t y = rect.y0; y < rect.y1; ++y)
    for (uint32_t x = rect.x0; x < rect.x1; ++x) {
      const float d = depth[size_t(y) * width + x];
      if (d <= 0.0f) continue;  // sky
      range.minDepth = std::min(range.minDepth, d);
      range.maxDepth = std::max(range.maxDepth, d);
    }
  return range;
}

template <typename T>
TileVolume<T> tileVolume(const ProjectionParams<T>& proj, const TileRect& rect, uint32_t width, uint32_t height,
                         T minDepth, T maxDepth) {
  TileVolume<T> v{};
  v.empty = !(maxDepth > T(0));
  // An empty tile gets a harmless range (no NaN anywhere); nothing is tested against it.
  if (v.empty) minDepth = maxDepth = T(1);
  const auto rays = tileCornerRays(proj, rect, width, height);
  const auto sides = tileSidePlanes(rays);
  v.zNear = viewZFromDepth(maxDepth, proj);
  v.zFar = viewZFromDepth(minDepth, proj);
  for (int i = 0; i < 4; ++i) v.planes[i] = sides[i];
  v.planes[4] = {glm::vec<3, T>(0, 0, -1), v.zNear};  // -z + zNear >= 0 ⇔ z <= zNear
  v.planes[5] = {glm::vec<3, T>(0, 0, 1), -v.zFar};   // z - zFar >= 0 ⇔ z >= zFar
  for (int i = 0; i < 4; ++i) {
    v.corners[i] = rays[i] * -v.zNear;
    v.corners[4 + i] = rays[i] * -v.zFar;
  }
  v.aabbMin = v.aabbMax = v.corners[0];
  for (const auto& c : v.corners) {
    v.aabbMin = glm::min(v.aabbMin, c);
    v.aabbMax = glm::max(v.aabbMax, c);
  }
  return v;
}

double spotConeTan(double outerConeAngle) {
  return outerConeAngle <= kMaxConeCullAngle ? std::tan(std::max(outerConeAngle, 0.0)) : -1.0;
}

template <typename T>
ViewLight<T> toViewLight(const Light& light, const glm::mat<4, 4, T>& view) {
  using V3 = glm::vec<3, T>;
  ViewLight<T> l{};
  l.type = light.type;
  l.position = V3(view * glm::vec<4, T>(V3(light.position), T(1)));
  l.direction = glm::normalize(glm::mat<3, 3, T>(view) * V3(light.direction));
  l.range = T(light.range);
  // glTF limits the outer angle to [0, pi/2]; float(pi/2) is slightly above pi/2, so clamp.
  const double outer = std::clamp(double(light.outerConeAngle), 0.0, 1.57079632679489662);
  l.tanOuter = T(spotConeTan(outer));
  l.cosOuter = T(std::cos(outer));
  l.sinOuter = T(std::sin(outer));
  l.worldScale = glm::length(V3(light.position)) + glm::length(V3(view[3]));
  return l;
}

template <typename T>
bool sphereOutsidePlane(const Plane<T>& plane, const glm::vec<3, T>& centre, T radius) {
  return glm::dot(plane.n, centre) + plane.d < -radius;
}

template <typename T>
bool coneOutsidePlane(const Plane<T>& plane, const glm::vec<3, T>& tip, const glm::vec<3, T>& axis, T height,
                      T baseRadius) {
  if (!(glm::dot(plane.n, tip) + plane.d < T(0))) return false;
  // cross(cross(a, n), a) = n - (a·n) a for unit a; built from the small cross(a, n) it keeps its
  // direction accurate even when n is nearly parallel to a (no cancellation in n - (a·n) a).
  const glm::vec<3, T> v = glm::cross(glm::cross(axis, plane.n), axis);
  const T len2 = glm::dot(v, v);
  glm::vec<3, T> q = tip + axis * height;
  if (len2 > T(0)) q += v * (baseRadius / std::sqrt(len2));
  return glm::dot(plane.n, q) + plane.d < T(0);
}

template <typename T>
bool sphereOverlapsAabb(const glm::vec<3, T>& lo, const glm::vec<3, T>& hi, const glm::vec<3, T>& centre, T radius) {
  T d2 = T(0);
  for (int i = 0; i < 3; ++i) {
    if (centre[i] < lo[i])
      d2 += (lo[i] - centre[i]) * (lo[i] - centre[i]);
    else if (centre[i] > hi[i])
      d2 += (centre[i] - hi[i]) * (centre[i] - hi[i]);
  }
  return d2 <= radius * radius;
}

template <typename T>
bool lightPassesPlanes(const TileVolume<T>& tile, const ViewLight<T>& light) {
  if (light.type == LightType::Directional) return true;
  for (const auto& p : tile.planes)
    if (sphereOutsidePlane(p, light.position, light.range)) return false;
  if (light.type == LightType::Spot && light.tanOuter >= T(0)) {
    // Height = range: a sector point at distance <= range has axial coordinate <= range, so the
    // cone of height range contains the sector.
    const T baseRadius = light.range * light.tanOuter;
    for (const auto& p : tile.planes)
      if (coneOutsidePlane(p, light.position, light.direction, light.range, baseRadius)) return false;
  }
  return true;
}

template <typename T>
bool lightPassesAabb(const TileVolume<T>& tile, const ViewLight<T>& light) {
  if (light.type == LightType::Directional) return true;
  return sphereOverlapsAabb(tile.aabbMin, tile.aabbMax, light.position, light.range);
}

template <typename T>
uint32_t sliceOf(const TileVolume<T>& tile, T z) {
  const T u = std::floor((tile.zNear - z) * tile.sliceScale);
  return uint32_t(std::min(std::max(u, T(0)), T(tile.slices - 1)));
}

template <typename T>
void applyDepthSlices(TileVolume<T>& tile, uint32_t slices, const ProjectionParams<T>& proj,
                      const std::vector<float>& depth, uint32_t width, uint32_t height, const TileRect& rect) {
  HB_ASSERT(slices == 0 || (slices >= 2 && slices <= 32));
  HB_ASSERT(depth.size() == size_t(width) * height && rect.x1 <= width && rect.y1 <= height);
  tile.slices = slices;
  tile.depthMask = 0;
  if (slices == 0 || tile.empty) return;
  // zNear == zFar: every pixel and every light falls in slab 0 and the slab test keeps all.
  tile.sliceScale = tile.zNear > tile.zFar ? T(slices) / (tile.zNear - tile.zFar) : T(0);
  for (uint32_t y = rect.y0; y < rect.y1; ++y)
    for (uint32_t x = rect.x0; x < rect.x1; ++x) {
      const float d = depth[size_t(y) * width + x];
      if (d <= 0.0f) continue;  // sky
      tile.depthMask |= 1u << sliceOf(tile, viewZFromDepth(T(d), proj));
    }
}

template <typename T>
T sliceWidening(const TileVolume<T>& tile, const ViewLight<T>& light) {
  const T u = T(0x1p-24);
  return T(16) * u * (std::abs(tile.zFar) + std::abs(light.position.z) + light.range + light.worldScale);
}

template <typename T>
uint32_t lightSliceMask(const TileVolume<T>& tile, const ViewLight<T>& light) {
  const T reach = light.range + sliceWidening(tile, light);
  const uint32_t lo = sliceOf(tile, light.position.z + reach);  // nearest point: the largest z
  const uint32_t hi = sliceOf(tile, light.position.z - reach);
  return (0xFFFFFFFFu >> (31u - hi)) & (0xFFFFFFFFu << lo);
}

template <typename T>
bool lightTouchesTile(const TileVolume<T>& tile, const ViewLight<T>& light, bool useAabb) {
  if (tile.empty) return false;
  if (!lightPassesPlanes(tile, light)) return false;
  if (useAabb && !lightPassesAabb(tile, light)) return false;
  if (tile.slices > 0 && light.type != LightType::Directional && (lightSliceMask(tile, light) & tile.depthMask) == 0)
    return false;
  return true;
}

template <typename T>
TileLightList cullTile(const TileVolume<T>& tile, const std::vector<ViewLight<T>>& lights, bool useAabb,
                       uint32_t capacity) {
  TileLightList list;
  for (uint32_t i = 0; i < lights.size(); ++i) {
    if (!lightTouchesTile(tile, lights[i], useAabb)) continue;
    if (list.total < capacity) list.indices.push_back(i);
    ++list.total;
  }
  return list;
}

// ---------------------------------------------------------------------------------------------
// Exact reference.

static double planeDistance(const Plane<double>& p, const glm::dvec3& x) { return glm::dot(p.n, x) + p.d; }

static double distanceToSegment(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return glm::length(p - (a + t * ab));
}

static constexpr int kEdges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                      {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};

double distanceToTileVolume(const TileVolume<double>& tile, const glm::dvec3& p) {
  bool inside = true;
  for (const auto& pl : tile.planes) inside = inside && planeDistance(pl, p) >= 0.0;
  if (inside) return 0.0;
  double scale = 1.0;
  for (const auto& c : tile.corners) scale = std::max(scale, glm::length(c));
  // Slack for "the projection lies in the face": a few ulps of the coordinates. It only lets a
  // projection a rounding error outside count, which errs towards "meets" (conservative).
  const double slack = 64.0 * std::numeric_limits<double>::epsilon() * (scale + glm::length(p));
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 6; ++i) {
    const double s = planeDistance(tile.planes[i], p);
    if (s >= 0.0) continue;  // the closest point lies on a face whose plane p is outside of
    const glm::dvec3 q = p - s * tile.planes[i].n;
    bool inFace = true;
    for (int j = 0; j < 6; ++j)
      if (j != i && planeDistance(tile.planes[j], q) < -slack) inFace = false;
    if (inFace) best = std::min(best, -s);
  }
  for (const auto& e : kEdges) best = std::min(best, distanceToSegment(p, tile.corners[e[0]], tile.corners[e[1]]));
  return best;
}

namespace {

// Spherical sector: tip, unit axis, radius, half-angle (cos, sin), 0 <= angle <= 90°.
struct Sector {
  glm::dvec3 tip, axis;
  double radius, cosA, sinA;

  glm::dvec3 support(const glm::dvec3& u) const {
    const double len = glm::length(u);
    if (len == 0.0) return tip;
    const glm::dvec3 uh = u / len;
    const double ca = glm::dot(uh, axis);
    if (ca >= cosA) return tip + radius * uh;  // u inside the cone: a point of the spherical cap
    const glm::dvec3 perp = uh - ca * axis;
    const double lp = glm::length(perp);
    if (lp == 0.0) return tip;  // u = -axis: with angle <= 90° every point has dot(u, p - tip) <= 0
    // The cone generator nearest to u lies in the plane of axis and u.
    const glm::dvec3 g = cosA * axis + sinA * (perp / lp);
    return glm::dot(uh, g) > 0.0 ? tip + radius * g : tip;
  }
};

glm::dvec3 polytopeSupport(const std::array<glm::dvec3, 8>& pts, const glm::dvec3& u) {
  glm::dvec3 best = pts[0];
  double bestDot = glm::dot(pts[0], u);
  for (const auto& p : pts)
    if (glm::dot(p, u) > bestDot) bestDot = glm::dot(p, u), best = p;
  return best;
}

// Closest point to the origin of the convex hull of the points `s` (1..4 of them): the minimum
// over all subsets whose affine-hull projection of the origin has non-negative barycentric
// coordinates (the true closest point lies in the relative interior of one face, which is such a
// subset; every other accepted candidate is a hull point, so no smaller). Reduces s to the subset.
glm::dvec3 closestOnHull(std::vector<glm::dvec3>& s) {
  const int n = int(s.size());
  HB_ASSERT(n >= 1 && n <= 4);
  double bestN2 = std::numeric_limits<double>::infinity();
  glm::dvec3 best(0.0);
  int bestMask = 1;
  for (int mask = 1; mask < (1 << n); ++mask) {
    int idx[4] = {}, k = 0;
    for (int i = 0; i < n; ++i)
      if (mask & (1 << i)) idx[k++] = i;
    const glm::dvec3 p0 = s[idx[0]];
    // Minimise |p0 + E mu|²: normal equations (E^T E) mu = -E^T p0, solved by Cramer's rule.
    double g[3][3] = {}, rhs[3] = {}, mu[3] = {};
    glm::dvec3 e[3];
    for (int i = 1; i < k; ++i) e[i - 1] = s[idx[i]] - p0;
    const int m = k - 1;
    for (int i = 0; i < m; ++i) {
      rhs[i] = -glm::dot(e[i], p0);
      for (int j = 0; j < m; ++j) g[i][j] = glm::dot(e[i], e[j]);
    }
    bool ok = true;
    if (m == 1) {
      ok = g[0][0] > 0.0;
      if (ok) mu[0] = rhs[0] / g[0][0];
    } else if (m >= 2) {
      glm::dmat3 gm(1.0);
      for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j) gm[j][i] = g[i][j];
      glm::dvec3 r(rhs[0], rhs[1], m == 3 ? rhs[2] : 0.0);
      // For m == 2 the 3x3 system has an identity third row/column: same solution.
      const double det = glm::determinant(gm);
      double scale = 1.0;
      for (int i = 0; i < m; ++i) scale *= g[i][i];
      ok = std::abs(det) > 1e-12 * scale;  // affinely dependent points: a smaller subset covers them
      if (ok) {
        const glm::dvec3 sol = glm::inverse(gm) * r;
        mu[0] = sol.x, mu[1] = sol.y, mu[2] = sol.z;
      }
    }
    if (!ok) continue;
    double lambda0 = 1.0;
    bool nonNegative = true;
    glm::dvec3 x = p0;
    for (int i = 0; i < m; ++i) {
      lambda0 -= mu[i];
      nonNegative = nonNegative && mu[i] >= 0.0;
      x += mu[i] * e[i];
    }
    if (!nonNegative || lambda0 < 0.0) continue;
    // Four affinely independent points span R³: the origin is its own projection, and it lies in
    // the tetrahedron (non-negative barycentrics). Ill-conditioned solves must not blur that.
    if (m == 3) x = glm::dvec3(0.0);
    const double n2 = glm::dot(x, x);
    if (n2 < bestN2) bestN2 = n2, best = x, bestMask = mask;
  }
  std::vector<glm::dvec3> kept;
  for (int i = 0; i < n; ++i)
    if (bestMask & (1 << i)) kept.push_back(s[i]);
  s = kept;
  return best;
}

// GJK [Gilbert, Johnson, Keerthi 1988] on the Minkowski difference polytope − sector: the sets
// meet iff the origin is in it. w = support(-v) minimises dot(v, x) over the difference, so
// dot(v, w) > 0 puts every point of it strictly on one side of a plane that misses the origin.
bool polytopeMeetsSector(const std::array<glm::dvec3, 8>& pts, const Sector& sector, double scale) {
  auto support = [&](const glm::dvec3& u) { return polytopeSupport(pts, u) - sector.support(-u); };
  std::vector<glm::dvec3> simplex;
  glm::dvec3 v = pts[0] - sector.tip;
  const double tiny = 1e-12 * scale;
  for (int iter = 0; iter < 200; ++iter) {
    const glm::dvec3 w = support(-v);
    if (glm::dot(v, w) > 0.0) return false;  // separating plane {x : dot(v, x) = dot(v, w)}
    simplex.push_back(w);
    v = closestOnHull(simplex);
    if (glm::dot(v, v) <= tiny * tiny) return true;
  }
  return true;  // not converged: only touching configurations do this; count them as meeting
}

}  // namespace

bool exactLightMeetsTile(const TileVolume<double>& tile, const ViewLight<double>& light) {
  if (tile.empty) return false;
  if (light.type == LightType::Directional) return true;
  const double dist = distanceToTileVolume(tile, light.position);
  if (dist > light.range) return false;  // every light volume lies in its range ball
  if (light.type == LightType::Point || light.cosOuter <= 0.0) return true;  // ball (>= 90°: ball)
  if (dist == 0.0) return true;                                              // tip inside the tile
  double scale = light.range + glm::length(light.position);
  for (const auto& c : tile.corners) scale = std::max(scale, glm::length(c));
  const Sector sector{light.position, light.direction, light.range, light.cosOuter, light.sinOuter};
  return polytopeMeetsSector(tile.corners, sector, scale);
}

// ---------------------------------------------------------------------------------------------
// Statistics.

uint64_t cullingMemoryBytes(uint32_t width, uint32_t height, uint32_t tileSize, uint32_t capacity) {
  const uint64_t tiles = uint64_t(tileCount(width, tileSize)) * tileCount(height, tileSize);
  return tiles * 16u + tiles * 4u * capacity;
}

CullStatistics cullStatistics(const std::vector<TileLightList>& kept, const std::vector<std::vector<uint32_t>>& exact,
                              uint32_t width, uint32_t height, uint32_t tileSize, uint32_t capacity) {
  HB_ASSERT(kept.size() == exact.size());
  HB_ASSERT(kept.size() == uint64_t(tileCount(width, tileSize)) * tileCount(height, tileSize));
  CullStatistics s;
  s.tiles = kept.size();
  uint64_t totalSum = 0;
  for (size_t t = 0; t < kept.size(); ++t) {
    const auto& stored = kept[t].indices;
    const auto& truth = exact[t];
    const bool overflow = kept[t].total > stored.size();
    s.storedPairs += stored.size();
    s.exactPairs += truth.size();
    totalSum += kept[t].total;
    s.maxLightsPerTile = std::max(s.maxLightsPerTile, kept[t].total);
    if (overflow) ++s.overflowTiles;
    for (uint32_t i : stored)
      if (!std::binary_search(truth.begin(), truth.end(), i)) ++s.falsePositives;
    for (uint32_t i : truth)
      if (!std::binary_search(stored.begin(), stored.end(), i)) ++(overflow ? s.droppedByOverflow : s.falseNegatives);
  }
  s.falsePositiveRate = s.storedPairs ? double(s.falsePositives) / double(s.storedPairs) : 0.0;
  s.meanLightsPerTile = s.tiles ? double(totalSum) / double(s.tiles) : 0.0;
  s.memoryBytes = cullingMemoryBytes(width, height, tileSize, capacity);
  return s;
}

void addGeometryStatistics(CullStatistics& s, const std::vector<TileLightList>& kept,
                           const std::vector<std::vector<uint32_t>>& needed, bool sliced) {
  HB_ASSERT(kept.size() == needed.size() && kept.size() == s.tiles);
  s.neededPairs = s.uselessPairs = s.missedNeeded = 0;
  for (size_t t = 0; t < kept.size(); ++t) {
    const auto& stored = kept[t].indices;
    const auto& need = needed[t];
    const bool overflow = kept[t].total > stored.size();
    s.neededPairs += need.size();
    for (uint32_t i : stored)
      if (!std::binary_search(need.begin(), need.end(), i)) ++s.uselessPairs;
    for (uint32_t i : need)
      if (!overflow && !std::binary_search(stored.begin(), stored.end(), i)) ++s.missedNeeded;
  }
  s.uselessRate = s.storedPairs ? double(s.uselessPairs) / double(s.storedPairs) : 0.0;
  if (sliced) {
    s.slicedAway = s.falseNegatives;
    s.falseNegatives = s.missedNeeded;
  }
}

// Explicit instantiations: float mirrors the GPU, double is the reference.
#define HB_CULL_INSTANTIATE(T)                                                                                    \
  template std::array<glm::vec<3, T>, 4> tileCornerRays(const ProjectionParams<T>&, const TileRect&, uint32_t,    \
                                                        uint32_t);                                                \
  template std::array<Plane<T>, 4> tileSidePlanes(const std::array<glm::vec<3, T>, 4>&);                          \
  template T viewZFromDepth(T, const ProjectionParams<T>&);                                                       \
  template TileVolume<T> tileVolume(const ProjectionParams<T>&, const TileRect&, uint32_t, uint32_t, T, T);       \
  template ViewLight<T> toViewLight(const Light&, const glm::mat<4, 4, T>&);                                      \
  template bool sphereOutsidePlane(const Plane<T>&, const glm::vec<3, T>&, T);                                    \
  template bool coneOutsidePlane(const Plane<T>&, const glm::vec<3, T>&, const glm::vec<3, T>&, T, T);            \
  template bool sphereOverlapsAabb(const glm::vec<3, T>&, const glm::vec<3, T>&, const glm::vec<3, T>&, T);       \
  template bool lightPassesPlanes(const TileVolume<T>&, const ViewLight<T>&);                                     \
  template bool lightPassesAabb(const TileVolume<T>&, const ViewLight<T>&);                                       \
  template bool lightTouchesTile(const TileVolume<T>&, const ViewLight<T>&, bool);                                \
  template uint32_t sliceOf(const TileVolume<T>&, T);                                                             \
  template void applyDepthSlices(TileVolume<T>&, uint32_t, const ProjectionParams<T>&, const std::vector<float>&, \
                                 uint32_t, uint32_t, const TileRect&);                                            \
  template T sliceWidening(const TileVolume<T>&, const ViewLight<T>&);                                            \
  template uint32_t lightSliceMask(const TileVolume<T>&, const ViewLight<T>&);                                    \
  template TileLightList cullTile(const TileVolume<T>&, const std::vector<ViewLight<T>>&, bool, uint32_t);
HB_CULL_INSTANTIATE(float)
HB_CULL_INSTANTIATE(double)
#undef HB_CULL_INSTANTIATE

}  // namespace hb
