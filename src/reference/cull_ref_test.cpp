#include "reference/cull_ref.h"
#include "base/numbers.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "scene/camera.h"

namespace hb {
namespace {

// One randomised light/tile case, camera independent: a random projection, resolution, tile size,
// tile, depth range and light placed near the tile's frustum (so that many cases are close calls).
struct Case {
  ProjectionParams<double> proj;
  uint32_t width, height;
  TileRect rect;
  float minDepth, maxDepth;
  ViewLight<double> light;
};

double logUniform(std::mt19937_64& rng, double lo, double hi) {
  return std::exp(std::uniform_real_distribution<double>(std::log(lo), std::log(hi))(rng));
}

Case randomCase(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  Case c{};
  const double aspect = 0.5 + 2.0 * u01(rng);
  const double yfov = (20.0 + 100.0 * u01(rng)) * kPi / 180.0;
  const double zn = logUniform(rng, 0.01, 1.0);
  const double zf = zn * logUniform(rng, 10.0, 1e5);
  c.proj = projectionParams(reverseZProjectionD(aspect, yfov, zn, zf));
  c.width = 1 + uint32_t(u01(rng) * 2560);
  c.height = 1 + uint32_t(u01(rng) * 1600);
  const uint32_t sizes[3] = {8, 16, 32};
  const uint32_t ts = sizes[rng() % 3];
  c.rect = tileRect(uint32_t(rng() % tileCount(c.width, ts)), uint32_t(rng() % tileCount(c.height, ts)), ts, c.width,
                    c.height);
  // Depths of surfaces at log-uniform view distances; sometimes a flat tile, rarely a sky tile.
  auto depthAt = [&](double dist) { return float(c.proj.d / dist - c.proj.c); };  // inverse of viewZ
  float d1 = depthAt(logUniform(rng, zn, zf)), d2 = depthAt(logUniform(rng, zn, zf));
  const double kind = u01(rng);
  if (kind < 0.05) d2 = d1;
  c.minDepth = std::min(d1, d2);
  c.maxDepth = std::max(d1, d2);
  if (kind > 0.98) c.minDepth = 1.0f, c.maxDepth = 0.0f;

  // Light near the tile frustum: a point on a random ray through the tile (a bit beyond its
  // sides) at a random depth from behind the camera to beyond the far bound, plus a radius
  // comparable with the frustum's cross-section there.
  const auto rays = tileCornerRays(c.proj, c.rect, c.width, c.height);
  const double a = -0.5 + 2.0 * u01(rng), b = -0.5 + 2.0 * u01(rng);
  const glm::dvec3 ray = glm::mix(glm::mix(rays[0], rays[1], a), glm::mix(rays[3], rays[2], a), b);
  const double zNear = -c.proj.d / (double(c.maxDepth) + c.proj.c);
  const double zFar = -c.proj.d / (double(c.minDepth) + c.proj.c);
  const double z = glm::mix(zNear * 0.5, zFar * 1.5, u01(rng)) + (u01(rng) < 0.05 ? 2.0 * zn : 0.0);
  const double across = glm::length(rays[0] - rays[2]) * std::abs(z) + std::abs(zFar - zNear) + zn;
  Light l;
  const double t = u01(rng);
  l.type = t < 0.45 ? LightType::Point : (t < 0.97 ? LightType::Spot : LightType::Directional);
  l.range = float(across * logUniform(rng, 0.01, 10.0));
  const glm::dvec3 pos = ray * -z + glm::dvec3(u01(rng) - 0.5, u01(rng) - 0.5, u01(rng) - 0.5) * across;
  std::normal_distribution<double> g;
  glm::dvec3 dir(g(rng), g(rng), g(rng));
  if (u01(rng) < 0.2) dir = glm::dvec3(0.0) - pos;  // aimed at the eye: crosses the tile's planes
  const double angle = u01(rng);
  l.outerConeAngle = float(angle < 0.05 ? kPi / 2 : (angle < 0.08 ? 0.0 : angle * kPi / 2));
  // Identity view: the light is given in view space directly.
  l.position = glm::vec3(pos);
  l.direction = glm::vec3(glm::normalize(dir));
  c.light = toViewLight(l, glm::dmat4(1.0));
  return c;
}

// A case whose range sphere just touches (or just misses) the tile: the range is the exact
// distance times 1 ± `relative`; the close calls that rounding decides.
Case tangentCase(std::mt19937_64& rng, double relative) {
  for (;;) {
    Case c = randomCase(rng);
    if (c.maxDepth <= 0.0f || c.light.type == LightType::Directional) continue;
    const auto vol = tileVolume(c.proj, c.rect, c.width, c.height, double(c.minDepth), double(c.maxDepth));
    const double dist = distanceToTileVolume(vol, c.light.position);
    if (dist <= 0.0) continue;
    c.light.range = dist * (1.0 + relative * std::uniform_real_distribution<double>(-1.0, 1.0)(rng));
    return c;
  }
}

TileVolume<double> volumeOf(const Case& c) {
  return tileVolume(c.proj, c.rect, c.width, c.height, double(c.minDepth), double(c.maxDepth));
}

TEST(LightCulling, NeverDropsALightThatTouchesTheTile) {
  std::mt19937_64 rng(20240601);
  uint64_t fnPlanes = 0, fnAabb = 0, fpPlanes = 0, fpAabb = 0, hits = 0;
  constexpr int kCases = 1000000;
  for (int i = 0; i < kCases; ++i) {
    // One case in ten is tangent to within 1e-9 (far above double rounding, ~1e-16 relative).
    const Case c = i % 10 == 0 ? tangentCase(rng, 1e-9) : randomCase(rng);
    const auto vol = volumeOf(c);
    const bool exact = exactLightMeetsTile(vol, c.light);
    const bool planes = lightTouchesTile(vol, c.light, false);
    const bool both = lightTouchesTile(vol, c.light, true);
    hits += exact;
    fnPlanes += exact && !planes;
    fnAabb += exact && !both;
    fpPlanes += !exact && planes;
    fpAabb += !exact && both;
    ASSERT_FALSE(exact && !both) << "case " << i;
  }
  EXPECT_EQ(fnPlanes, 0u);
  EXPECT_EQ(fnAabb, 0u);
  EXPECT_LE(fpAabb, fpPlanes);
  // The generator must produce a real mix, or the test proves nothing.
  EXPECT_GT(hits, kCases / 10u);
  EXPECT_GT(fpPlanes, 1000u);
  EXPECT_LT(fpAabb, fpPlanes);
  std::printf("exact hits %llu, FP planes %llu, FP planes+AABB %llu\n", (unsigned long long)hits,
              (unsigned long long)fpPlanes, (unsigned long long)fpAabb);
}

// The exact distance is a lower bound of every sampled hull point's distance and an upper bound
// of every plane's outside distance (both hold for any convex polyhedron).
TEST(LightCulling, ExactDistanceIsBracketedBySamplesAndPlanes) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  for (int i = 0; i < 20000; ++i) {
    const Case c = randomCase(rng);
    if (c.maxDepth <= 0.0f) continue;
    const auto vol = volumeOf(c);
    const double dist = distanceToTileVolume(vol, c.light.position);
    double lower = 0.0;
    for (const auto& p : vol.planes) lower = std::max(lower, -(glm::dot(p.n, c.light.position) + p.d));
    double scale = glm::length(c.light.position);
    for (const auto& p : vol.corners) scale = std::max(scale, glm::length(p));
    const double tol = 1e-12 * scale;  // a few hundred ulps of the coordinates in double
    EXPECT_GE(dist, lower - tol);
    for (int s = 0; s < 20; ++s) {
      double w[8], sum = 0.0;
      for (double& x : w) sum += (x = -std::log(1.0 - u01(rng)));
      glm::dvec3 p(0.0);
      for (int k = 0; k < 8; ++k) p += w[k] / sum * vol.corners[k];
      EXPECT_LE(dist, glm::length(p - c.light.position) + tol);
    }
  }
}

// Where GJK says a spot's sector misses the tile, no sampled sector point lies in the tile.
TEST(LightCulling, ExactSpotMissHasNoSectorPointInTheTile) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  int misses = 0;
  for (int i = 0; i < 20000 && misses < 3000; ++i) {
    const Case c = randomCase(rng);
    if (c.light.type != LightType::Spot || c.maxDepth <= 0.0f) continue;
    const auto vol = volumeOf(c);
    if (exactLightMeetsTile(vol, c.light) || distanceToTileVolume(vol, c.light.position) > c.light.range) continue;
    ++misses;
    const glm::dvec3 a = c.light.direction;
    const glm::dvec3 t1 =
        glm::normalize(glm::cross(a, std::abs(a.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
    const glm::dvec3 t2 = glm::cross(a, t1);
    const double outer = std::atan2(c.light.sinOuter, c.light.cosOuter);
    for (int s = 0; s < 200; ++s) {
      const double th = outer * std::sqrt(u01(rng)), ph = 2 * kPi * u01(rng);
      const double r = c.light.range * std::cbrt(u01(rng));
      const glm::dvec3 p =
          c.light.position + r * (std::cos(th) * a + std::sin(th) * (std::cos(ph) * t1 + std::sin(ph) * t2));
      bool inside = true;
      for (const auto& pl : vol.planes) inside = inside && glm::dot(pl.n, p) + pl.d > 1e-9 * r;
      ASSERT_FALSE(inside) << "case " << i;
    }
  }
  EXPECT_GT(misses, 100);
}

// Float mirrors the GPU; it may disagree with double only where some comparison is closer to its
// threshold than float rounding can move it. Error bound (u = 2^-24), derived per step:
//  ray component: px/W (u), -1 (u·|ndc|+u), A and B cast from double (u), /A (u) → ≤ 6u·R,
//    R = max(1, |ray component|);
//  side normal = cross(p, q)/|cross|: inputs 2·6√2u·|p||q|, products and difference 2u·|p||q| →
//    |δc| ≤ 21u·|p||q|; direction error ≤ 21u·cond + 2u with cond = |p||q|/|cross(p, q)| (large
//    for small tiles: nearly parallel corner rays);
//  signed distance n·x + d: |δn|·|x| + dot rounding 3u|x| + centre cast u|x|; near/far z =
//    -D/(d+C): 4u|z|, and the subtraction u(|x|+|z|);
//  AABB corners ray·(-z): (6√2 + 4 + 1)u·R|z| ≤ 14u·R|z|, and d² rounding 1.5u·distance;
//  cone Q: axis cast and normalisation 4u, v's direction ⟂-error only enters n·v via a·δv, so
//    all cone terms stay within (|δn| + 8u)·(|tip| + h + rBase).
// Summing with everything scaled by S = |centre| + range·(1 + max(tanOuter, 0)) + 2R·|zFar|:
//    bound = (21·cond + 32)·u·S.
TEST(LightCulling, FloatAgreesWithDoubleExceptWithinRoundingMargin) {
  std::mt19937_64 rng(99);
  int mismatches = 0;
  for (int i = 0; i < 200000; ++i) {
    // Half the cases are tangent to within 1e-6: float rounding (~6e-8 relative) decides some.
    const Case c = i % 2 ? tangentCase(rng, 1e-6) : randomCase(rng);
    const auto vd = volumeOf(c);
    const ProjectionParams<float> pf{float(c.proj.a), float(c.proj.b), float(c.proj.c), float(c.proj.d)};
    const auto vf = tileVolume(pf, c.rect, c.width, c.height, c.minDepth, c.maxDepth);
    ViewLight<float> lf{c.light.type,           glm::vec3(c.light.position), glm::vec3(c.light.direction),
                        float(c.light.range),   float(c.light.tanOuter),     float(c.light.cosOuter),
                        float(c.light.sinOuter)};
    for (int aabb = 0; aabb < 2; ++aabb) {
      const bool d = lightTouchesTile(vd, c.light, aabb);
      const bool f = lightTouchesTile(vf, lf, aabb);
      if (d == f) continue;
      ++mismatches;
      // Smallest distance of any comparison to its threshold, in double.
      const auto& l = c.light;
      double closest = std::numeric_limits<double>::infinity();
      const double rBase = l.range * std::max(l.tanOuter, 0.0);
      for (const auto& p : vd.planes) {
        const double s = glm::dot(p.n, l.position) + p.d;
        closest = std::min({closest, std::abs(s + l.range), std::abs(s)});
        glm::dvec3 v = glm::cross(glm::cross(l.direction, p.n), l.direction);
        glm::dvec3 q = l.position + l.direction * l.range;
        if (glm::dot(v, v) > 0.0) q += glm::normalize(v) * rBase;
        closest = std::min(closest, std::abs(glm::dot(p.n, q) + p.d));
      }
      glm::dvec3 e = glm::max(glm::max(vd.aabbMin - l.position, l.position - vd.aabbMax), glm::dvec3(0.0));
      closest = std::min(closest, std::abs(glm::length(e) - l.range));
      const auto rays = tileCornerRays(c.proj, c.rect, c.width, c.height);
      double cond = 0.0, bigR = 1.0;
      for (int k = 0; k < 4; ++k) {
        const glm::dvec3 p = rays[k], q = rays[(k + 1) % 4];
        cond = std::max(cond, glm::length(p) * glm::length(q) / glm::length(glm::cross(p, q)));
        bigR = std::max({bigR, std::abs(p.x), std::abs(p.y)});
      }
      const double scale = glm::length(l.position) + l.range + rBase + 2.0 * bigR * std::abs(vd.zFar);
      const double bound = (21.0 * cond + 32.0) * kU * scale;
      EXPECT_LE(closest, bound) << "case " << i;
    }
  }
  EXPECT_GT(mismatches, 0);  // the close calls must actually occur, or the margin is untested
  std::printf("float/double decision mismatches within the margin: %d of 400000\n", mismatches);
}

// ---- hard cases ----

struct Fixture {
  ProjectionParams<double> proj = projectionParams(reverseZProjectionD(16.0 / 9.0, kPi / 3, 0.1, 1000.0));
  uint32_t width = 1920, height = 1080, tileSize = 16;
  double depthOf(double dist) const { return proj.d / dist - proj.c; }
  TileVolume<double> tile(uint32_t tx, uint32_t ty, double nearDist, double farDist) const {
    return tileVolume(proj, tileRect(tx, ty, tileSize, width, height), width, height, depthOf(farDist),
                      depthOf(nearDist));
  }
  static ViewLight<double> point(glm::dvec3 p, double range) {
    Light l;
    l.position = glm::vec3(p);
    l.range = float(range);
    return toViewLight(l, glm::dmat4(1.0));
  }
  static ViewLight<double> spot(glm::dvec3 p, glm::dvec3 dir, double range, double outer) {
    Light l;
    l.type = LightType::Spot;
    l.position = glm::vec3(p);
    l.direction = glm::vec3(glm::normalize(dir));
    l.range = float(range);
    l.outerConeAngle = float(outer);
    return toViewLight(l, glm::dmat4(1.0));
  }
};

bool keptEverywhere(const TileVolume<double>& t, const ViewLight<double>& l) {
  return lightTouchesTile(t, l, false) && lightTouchesTile(t, l, true) && exactLightMeetsTile(t, l);
}

TEST(LightCulling, SidePlanesPointIntoTheTileAndMatchTheEdges) {
  Fixture f;
  const auto t = f.tile(60, 33, 1.0, 50.0);
  const glm::dvec3 centre = (t.corners[0] + t.corners[2] + t.corners[4] + t.corners[6]) / 4.0;
  for (const auto& p : t.planes) {
    EXPECT_GT(glm::dot(p.n, centre) + p.d, 0.0);
    EXPECT_NEAR(glm::length(p.n), 1.0, 4e-16);  // normalisation: a few ulps
  }
  // Each side plane contains its two corner edges (through the eye).
  const int pairs[4][2] = {{3, 0}, {0, 1}, {1, 2}, {2, 3}};
  for (int i = 0; i < 4; ++i)
    for (int k : pairs[i]) EXPECT_NEAR(glm::dot(t.planes[i].n, t.corners[4 + k]), 0.0, 1e-12);
}

TEST(LightCulling, LightCentredOnATilePlaneIsKept) {
  Fixture f;
  const auto t = f.tile(10, 10, 2.0, 20.0);
  const glm::dvec3 onLeft = (t.corners[0] + t.corners[3] + t.corners[4] + t.corners[7]) / 4.0;
  EXPECT_TRUE(keptEverywhere(t, Fixture::point(onLeft, 1e-3)));
  const glm::dvec3 onNear = (t.corners[0] + t.corners[2]) / 2.0;
  EXPECT_TRUE(keptEverywhere(t, Fixture::point(onNear, 1e-3)));
}

TEST(LightCulling, RangeReachingIntoViewFromBehindTheCameraIsKept) {
  Fixture f;
  const auto t = f.tile(60, 33, 0.5, 10.0);                                   // tile at the image centre
  EXPECT_TRUE(keptEverywhere(t, Fixture::point({0, 0, 2.0}, 3.0)));           // reaches z = -1
  EXPECT_FALSE(lightTouchesTile(t, Fixture::point({0, 0, 2.0}, 2.4), true));  // stops at z = -0.4
  EXPECT_FALSE(exactLightMeetsTile(t, Fixture::point({0, 0, 2.0}, 2.4)));
}

TEST(LightCulling, CameraInsideALightsSphereKeepsIt) {
  Fixture f;
  for (uint32_t tx : {0u, 60u, 119u})
    EXPECT_TRUE(keptEverywhere(f.tile(tx, 0, 1.0, 4.0), Fixture::point({0, 0, 0}, 5.0)));
}

TEST(LightCulling, LightStraddlingTheNearBoundIsKept) {
  Fixture f;
  const auto t = f.tile(60, 33, 5.0, 6.0);
  const glm::dvec3 c = (t.corners[0] + t.corners[2]) / 2.0;  // on the near face
  EXPECT_TRUE(keptEverywhere(t, Fixture::point(c + glm::dvec3(0, 0, 0.3), 0.5)));
  EXPECT_FALSE(lightTouchesTile(t, Fixture::point(c + glm::dvec3(0, 0, 0.6), 0.5), false));
}

TEST(LightCulling, SkyTileGetsNoLightAndNoNaN) {
  Fixture f;
  std::vector<float> depth(size_t(f.width) * f.height, 0.0f);
  const auto rect = tileRect(3, 4, f.tileSize, f.width, f.height);
  const auto range = tileDepthRange(depth, f.width, f.height, rect);
  EXPECT_TRUE(range.empty());
  const auto t = tileVolume(f.proj, rect, f.width, f.height, double(range.minDepth), double(range.maxDepth));
  EXPECT_TRUE(t.empty);
  for (const auto& c : t.corners) EXPECT_TRUE(std::isfinite(c.x + c.y + c.z));
  for (const auto& p : t.planes) EXPECT_TRUE(std::isfinite(p.n.x + p.n.y + p.n.z + p.d));
  Light dir;
  dir.type = LightType::Directional;
  const std::vector<ViewLight<double>> lights = {Fixture::point({0, 0, -5}, 1e6), toViewLight(dir, glm::dmat4(1.0))};
  const auto list = cullTile(t, lights, true);
  EXPECT_EQ(list.total, 0u);
  EXPECT_FALSE(exactLightMeetsTile(t, lights[1]));
}

TEST(LightCulling, DepthDiscontinuityBoundsTheTileByBothSurfaces) {
  Fixture f;
  std::vector<float> depth(size_t(f.width) * f.height, 0.0f);
  const auto rect = tileRect(60, 33, f.tileSize, f.width, f.height);
  for (uint32_t y = rect.y0; y < rect.y1; ++y)
    for (uint32_t x = rect.x0; x < rect.x1; ++x)
      depth[size_t(y) * f.width + x] = float(f.depthOf(x < rect.x0 + 5 ? 2.0 : 100.0));
  depth[size_t(rect.y0) * f.width + rect.x0 + 7] = 0.0f;  // a sky pixel does not widen the range
  const auto r = tileDepthRange(depth, f.width, f.height, rect);
  const auto t = tileVolume(f.proj, rect, f.width, f.height, double(r.minDepth), double(r.maxDepth));
  EXPECT_NEAR(t.zNear, -2.0, 2.0 * 1e-6);  // float depth: relative error ≲ 2u in z (reverse-Z)
  EXPECT_NEAR(t.zFar, -100.0, 100.0 * 1e-6);
  const glm::dvec3 axis = (t.corners[0] + t.corners[2]) / 2.0 / 2.0;  // ray at z = -1
  for (double z : {2.0, 50.0, 100.0}) EXPECT_TRUE(keptEverywhere(t, Fixture::point(axis * z, 0.01)));
  EXPECT_FALSE(lightTouchesTile(t, Fixture::point(axis * 101.0, 0.5), true));
}

TEST(LightCulling, SpotAxisParallelToAPlaneNormalIsHandled) {
  Fixture f;
  const auto t = f.tile(60, 33, 5.0, 6.0);
  const glm::dvec3 c = (t.corners[0] + t.corners[2]) / 2.0;
  // Axis = the near plane's normal (0,0,-1)... pointing into the tile: kept.
  EXPECT_TRUE(keptEverywhere(t, Fixture::spot(c + glm::dvec3(0, 0, 0.5), {0, 0, -1}, 1.0, 0.3)));
  // Pointing away from it (axis = -normal): the base disk is farthest along n at every point.
  const auto away = Fixture::spot(c + glm::dvec3(0, 0, 0.5), {0, 0, 1}, 1.0, 0.3);
  EXPECT_FALSE(lightTouchesTile(t, away, false));
  EXPECT_FALSE(exactLightMeetsTile(t, away));
  EXPECT_TRUE(coneOutsidePlane(t.planes[4], away.position, away.direction, 1.0, 1.0 * away.tanOuter));
}

TEST(LightCulling, SpotWithNinetyDegreeOuterAngleIsCulledAsItsSphere) {
  Fixture f;
  const auto t = f.tile(60, 33, 5.0, 6.0);
  const glm::dvec3 c = (t.corners[0] + t.corners[2]) / 2.0 + glm::dvec3(0, 0, 0.5);
  const auto s = Fixture::spot(c, {1, 0, 0}, 1.0, kPi / 2);
  EXPECT_LT(s.tanOuter, 0.0);  // no cone test: no inf from tan(90°)
  EXPECT_TRUE(keptEverywhere(t, s));
  const auto away = Fixture::spot(c, {0, 0, 1}, 1.0, kPi / 2);  // hemisphere facing away
  EXPECT_TRUE(lightTouchesTile(t, away, true));                 // conservative: the sphere
  EXPECT_FALSE(exactLightMeetsTile(t, away));
  EXPECT_TRUE(std::isfinite(spotConeTan(float(kPi / 2))) && spotConeTan(kPi / 2) < 0.0);
}

TEST(LightCulling, PartialEdgeTilesStopAtTheImageBorder) {
  const auto proj = projectionParams(reverseZProjectionD(100.0 / 37.0, 1.0, 0.1, 100.0));
  const uint32_t w = 100, h = 37, ts = 16;
  EXPECT_EQ(tileCount(w, ts), 7u);
  EXPECT_EQ(tileCount(h, ts), 3u);
  const auto rect = tileRect(6, 2, ts, w, h);
  EXPECT_EQ(rect.x1, 100u);
  EXPECT_EQ(rect.y1, 37u);
  const auto rays = tileCornerRays(proj, rect, w, h);
  EXPECT_DOUBLE_EQ(rays[2].x, 1.0 / proj.a);  // ndc x = +1
  EXPECT_DOUBLE_EQ(rays[2].y, 1.0 / proj.b);  // ndc y = +1 (bottom in Vulkan)
  // A light just inside the image's bottom-right corner is kept by that tile.
  const auto t = tileVolume(proj, rect, w, h, 0.5, 0.6);
  const glm::dvec3 p = rays[2] * -t.zNear * 0.999 + glm::dvec3(0, 0, -0.001);
  EXPECT_TRUE(keptEverywhere(t, Fixture::point(p, 1e-4)));
}

TEST(LightCulling, RangeFromEquation41CutsOffAtTheThreshold) {
  Fixture f;
  const auto t = f.tile(60, 33, 1.0, 1.5);
  const double range = rangeFromIntensity(100.0);  // sqrt(5000) = 70.71
  const glm::dvec3 nearCentre = (t.corners[0] + t.corners[2]) / 2.0;
  // Light straight ahead beyond the far bound: the closest tile point is on the far face, at
  // about |z| = 1.5; distance 70 keeps it, 72 does not.
  const glm::dvec3 dirAhead = glm::normalize(nearCentre);
  const auto in = Fixture::point(dirAhead * (1.5 + 70.0), range);
  const auto out = Fixture::point(dirAhead * (1.5 + 72.0), range);
  EXPECT_TRUE(keptEverywhere(t, in));
  EXPECT_FALSE(lightTouchesTile(t, out, false));
  EXPECT_FALSE(exactLightMeetsTile(t, out));
}

TEST(LightCulling, ListKeepsTheFirstLightsInOrderAndCountsOverflow) {
  Fixture f;
  const auto t = f.tile(60, 33, 1.0, 2.0);
  std::vector<ViewLight<double>> lights;
  const glm::dvec3 mid = (t.corners[0] + t.corners[2] + t.corners[4] + t.corners[6]) / 4.0;
  // Odd lights reach the tile, even ones are tiny and 1 unit off-axis; light 0 reaches it too.
  for (int i = 0; i < 40; ++i)
    lights.push_back(Fixture::point(mid + glm::dvec3(i % 2 ? 0.0 : 1.0, 0, 0), i % 2 ? 10.0 : 1e-3 + (i == 0)));
  // odd lights (20) + light 0 are kept: 21 lights.
  const auto list = cullTile(t, lights, true, 8);
  EXPECT_EQ(list.total, 21u);
  ASSERT_EQ(list.indices.size(), 8u);
  EXPECT_EQ(list.indices, (std::vector<uint32_t>{0, 1, 3, 5, 7, 9, 11, 13}));
}

TEST(CullStatistics, CountsFalsePositivesNegativesOverflowAndMemory) {
  // 2 tiles (a 16x8 image at 8 px tiles): tile 0 stores {1, 2} of exact {2, 3}: 1 FP, 1 FN;
  // tile 1 overflowed at capacity 2: stores {0, 1}, exact {0, 1, 4}: light 4 dropped by overflow.
  std::vector<TileLightList> kept = {{{1, 2}, 2}, {{0, 1}, 3}};
  std::vector<std::vector<uint32_t>> exact = {{2, 3}, {0, 1, 4}};
  const auto s = cullStatistics(kept, exact, 16, 8, 8, 2);
  EXPECT_EQ(s.falsePositives, 1u);
  EXPECT_EQ(s.falseNegatives, 1u);
  EXPECT_EQ(s.droppedByOverflow, 1u);
  EXPECT_EQ(s.overflowTiles, 1u);
  EXPECT_DOUBLE_EQ(s.falsePositiveRate, 0.25);
  EXPECT_DOUBLE_EQ(s.meanLightsPerTile, 2.5);
  EXPECT_EQ(s.maxLightsPerTile, 3u);
  EXPECT_EQ(s.memoryBytes, 2u * 16u + 2u * 4u * 2u);
  // 1920x1080: 120x68 tiles at 16 px, 240x135 at 8 px → about 4x the memory.
  EXPECT_EQ(cullingMemoryBytes(1920, 1080, 16, 32), 8160u * (16u + 128u));
  EXPECT_EQ(cullingMemoryBytes(1920, 1080, 8, 32), 32400u * (16u + 128u));
}

// ---- depth slices --------------------------------------------------------------------------------

// A tile cut into `slices` slabs between z = -2 and z = -10 (depths of those distances); pixels at
// z = -2 (slab 0) and z = -10 (the last slab) only.
struct SlicedTile {
  ProjectionParams<double> proj = projectionParams(reverseZProjectionD(16.0 / 9.0, 1.0, 0.1, 100.0));
  uint32_t width = 64, height = 32;
  TileRect rect = tileRect(1, 1, 16, 64, 32);
  std::vector<float> depth;
  TileVolume<double> tile;
  explicit SlicedTile(uint32_t slices) {
    depth.assign(size_t(width) * height, 0.0f);
    for (uint32_t y = rect.y0; y < rect.y1; ++y)
      for (uint32_t x = rect.x0; x < rect.x1; ++x)
        depth[size_t(y) * width + x] = float(proj.d / (x < rect.x0 + 8 ? 2.0 : 10.0) - proj.c);
    const auto r = tileDepthRange(depth, width, height, rect);
    tile = tileVolume(proj, rect, width, height, double(r.minDepth), double(r.maxDepth));
    applyDepthSlices(tile, slices, proj, depth, width, height, rect);
  }
};

TEST(DepthSlices, MaskHoldsTheSlabsOfThePixelsOnly) {
  const SlicedTile t(32);
  EXPECT_EQ(t.tile.depthMask, 0x80000001u);
  EXPECT_NEAR(t.tile.sliceScale, 32.0 / 8.0, 1e-5);
  // Outside the tile's range sliceOf clamps to the first and last slab (no UB, no wrap).
  EXPECT_EQ(sliceOf(t.tile, 5.0), 0u);
  EXPECT_EQ(sliceOf(t.tile, -1e30), 31u);
  EXPECT_EQ(sliceOf(t.tile, -6.1), 16u);  // 4.1 m past the near bound at 4 slabs per metre
}

TEST(DepthSlices, LightInTheGapIsDroppedAndLightsReachingEitherSurfaceAreKept) {
  const SlicedTile t(32);
  const glm::dvec3 axis = (t.tile.corners[0] + t.tile.corners[2]) / 2.0 / 2.0;  // ray at z = -1
  const TileVolume<double> plain = [&] {
    TileVolume<double> v = t.tile;
    v.slices = 0;
    return v;
  }();
  const auto gap = Fixture::point(axis * 6.1, 1.0);  // z from -5.1 to -7.1: u 12.4..20.4, slabs 12..20
  EXPECT_TRUE(lightTouchesTile(plain, gap, true));
  EXPECT_FALSE(lightTouchesTile(t.tile, gap, true));
  EXPECT_EQ(lightSliceMask(t.tile, gap), 0x001FF000u);
  EXPECT_TRUE(lightTouchesTile(t.tile, Fixture::point(axis * 6.0, 4.1), true));   // reaches 10 m
  EXPECT_TRUE(lightTouchesTile(t.tile, Fixture::point(axis * 3.0, 1.05), true));  // reaches 2 m
}

TEST(DepthSlices, FlatTileIsOneSlabAndKeepsWhatThePlanesKeep) {
  SlicedTile t(32);
  std::fill(t.depth.begin(), t.depth.end(), float(t.proj.d / 5.0 - t.proj.c));
  const auto r = tileDepthRange(t.depth, t.width, t.height, t.rect);
  auto tile = tileVolume(t.proj, t.rect, t.width, t.height, double(r.minDepth), double(r.maxDepth));
  applyDepthSlices(tile, 32, t.proj, t.depth, t.width, t.height, t.rect);
  EXPECT_EQ(tile.sliceScale, 0.0);
  EXPECT_EQ(tile.depthMask, 1u);
  const glm::dvec3 axis = (tile.corners[0] + tile.corners[2]) / 2.0 / -tile.zNear;  // ray at z = -1
  EXPECT_TRUE(lightTouchesTile(tile, Fixture::point(axis * 5.5, 0.6), false));
}

// In float, as the GPU runs it: the slab test never drops a light that the plane test keeps and
// that reaches a pixel in double; that is what sliceWidening is for. The close calls are built on
// purpose: a tile with pixels at a near and a far distance and, in between, a surface whose z lies
// on a slab boundary of the 32-slab cut (the float depth moves it by ~1e-7·|z| either way), and a
// light straight in front of one of its pixels whose range ends at that pixel's z to within float
// rounding, so the pixel's slab and the light's last slab are decided by rounding alone.
TEST(DepthSlices, FloatNeverDropsALightThatReachesAPixel) {
  std::mt19937_64 rng(20261122);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  uint64_t reaching = 0, tested = 0, straddling = 0;
  for (int i = 0; i < 200000; ++i) {
    const double zn = logUniform(rng, 0.01, 1.0), zf = zn * logUniform(rng, 100.0, 1e5);
    const glm::dmat4 projD = reverseZProjectionD(16.0 / 9.0, 1.0, zn, zf);
    const auto proj = projectionParams(projD);
    const uint32_t w = 128, h = 72, ts = 16;
    const TileRect rect = tileRect(uint32_t(rng() % 8), uint32_t(rng() % 5), ts, w, h);
    auto depthAt = [&](double dist) { return float(proj.d / dist - proj.c); };
    const double nearDist = logUniform(rng, zn, std::min(zf, 1e4) / 4);
    const double farDist = nearDist * logUniform(rng, 1.01, 4.0);
    // zNear and zFar as the tile will see them (from the float depths), then boundary k of 32.
    const double zNear = viewZFromDepth(double(depthAt(nearDist)), proj);
    const double zFar = viewZFromDepth(double(depthAt(farDist)), proj);
    const double zMid = zNear - double(1 + rng() % 31) * (zNear - zFar) / 32.0;
    std::vector<float> depth(size_t(w) * h, 0.0f);
    for (uint32_t y = rect.y0; y < rect.y1; ++y)
      for (uint32_t x = rect.x0; x < rect.x1; ++x) {
        const uint32_t pick = (x + y) % 3;
        depth[size_t(y) * w + x] = depthAt(pick == 0 ? nearDist : pick == 1 ? farDist : -zMid);
      }
    // A middle-surface pixel's view-space point (double, pixel centre).
    uint32_t px, py;
    do {
      px = rect.x0 + uint32_t(rng() % (rect.x1 - rect.x0));
      py = rect.y0 + uint32_t(rng() % (rect.y1 - rect.y0));
    } while ((px + py) % 3 != 2);
    const double z = viewZFromDepth(double(depth[size_t(py) * w + px]), proj);
    const glm::dvec3 p((2.0 * ((px + 0.5) / w) - 1.0) / proj.a * -z, (2.0 * ((py + 0.5) / h) - 1.0) / proj.b * -z, z);
    // The light in front of it (toward the camera) or behind it, its range ending at p.
    const double r0 = std::abs(z) * logUniform(rng, 1e-4, 0.2) * (u01(rng) < 0.5 ? 1.0 : -1.0);
    Light l;
    l.position = glm::vec3(p + glm::dvec3(0.0, 0.0, r0));
    l.range = float(std::abs(r0));
    if (glm::length(glm::dvec3(l.position) - p) > double(l.range)) continue;  // does not reach p
    ++reaching;
    const auto r = tileDepthRange(depth, w, h, rect);
    const auto projF = projectionParams(glm::mat4(projD));
    auto volF = tileVolume(projF, rect, w, h, r.minDepth, r.maxDepth);
    const ViewLight<float> lf = toViewLight(l, glm::mat4(1.0f));
    if (!lightTouchesTile(volF, lf, true)) continue;  // a plane-test close call: not this test's
    // The unwidened float decision at 32 slabs: how often rounding alone would have lost it.
    applyDepthSlices(volF, 32, projF, depth, w, h, rect);
    const float reach = lf.range;
    const uint32_t lo = sliceOf(volF, lf.position.z + reach), hi = sliceOf(volF, lf.position.z - reach);
    straddling += ((0xFFFFFFFFu >> (31u - hi)) & (0xFFFFFFFFu << lo) & volF.depthMask) == 0;
    for (uint32_t slices : {2u, 7u, 32u}) {
      applyDepthSlices(volF, slices, projF, depth, w, h, rect);
      ASSERT_TRUE(lightTouchesTile(volF, lf, true)) << "case " << i << " slices " << slices << " z " << z;
      ++tested;
    }
  }
  EXPECT_GT(tested, 100000u);
  EXPECT_GT(straddling, 100u);  // without the widening these would have been dropped
  std::printf("lights reaching a pixel %llu, slab tests %llu, dropped without widening %llu\n",
              (unsigned long long)reaching, (unsigned long long)tested, (unsigned long long)straddling);
}

}  // namespace
}  // namespace hb
