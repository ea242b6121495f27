#include "reference/bvh.h"
#include "reference/random_unit.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

namespace hb {
namespace {

// n random small triangles: centres uniform in [-spread, spread]^3, corners within `size` of them
// (the draws in the order the tests were written with, so each test sees its own scene).
template <class Rng>
std::vector<BvhTriangle> randomTriangles(Rng& rng, int n, double spread, double size) {
  std::uniform_real_distribution<double> u(-spread, spread), s(-size, size);
  std::vector<BvhTriangle> tris;
  for (int i = 0; i < n; ++i) {
    const glm::dvec3 c(u(rng), u(rng), u(rng));
    tris.push_back({c + glm::dvec3(s(rng), s(rng), s(rng)), c + glm::dvec3(s(rng), s(rng), s(rng)),
                    c + glm::dvec3(s(rng), s(rng), s(rng))});
  }
  return tris;
}

// Closed cube [-1, 1]³; each face is a fan of 4 triangles around its centre, so that the mesh has
// interior shared edges (the spokes) and an interior shared vertex (the centre) in a flat face,
// besides the convex cube edges and corners.
std::vector<BvhTriangle> cube() {
  std::vector<glm::dvec3> v;
  for (int i = 0; i < 8; ++i) v.emplace_back(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
  const int quads[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  std::vector<BvhTriangle> t;
  for (const auto& q : quads) {
    const glm::dvec3 centre = (v[q[0]] + v[q[2]]) / 2.0;  // exact: coordinates are ±1 and 0
    for (int k = 0; k < 4; ++k) t.push_back({centre, v[q[k]], v[q[(k + 1) % 4]]});
  }
  return t;
}

// pbrt-style watertightness property. From outside: rays aimed at points of the flat interior
// shared edges (spokes) and the shared centre vertex; the targets lie exactly in the face plane
// (the shared coordinate is exactly ±1), so the segment ends on the surface and must hit. (A ray
// that only grazes a convex cube edge may legitimately miss, so those are not targets from
// outside.) From inside the closed cube: every ray leaves through it, aimed at any edge (convex
// cube edges and corners included) or vertex.
TEST(Bvh, RaysThroughSharedEdgesAndVerticesOfAClosedCubeAreOccluded) {
  const auto tris = cube();
  const Bvh bvh(tris);
  ASSERT_EQ(bvh.triangleCount(), 24u);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  int rays = 0;
  for (const auto& t : tris) {
    const glm::dvec3 e[3][2] = {{t.v0, t.v1}, {t.v1, t.v2}, {t.v2, t.v0}};
    for (int k = 0; k < 3; ++k)
      for (int s = 0; s < 300; ++s) {
        const double f = s < 3 ? s * 0.5 : u01(rng);  // vertices, midpoints, random points
        const glm::dvec3 target = glm::mix(e[k][0], e[k][1], f);
        // Edges 0 and 2 of each fan triangle are spokes from the face centre; their far ends are
        // the cube's (convex) corners, left out from outside like the convex edges.
        const bool corner = std::abs(target.x) == 1.0 && std::abs(target.y) == 1.0 && std::abs(target.z) == 1.0;
        if (k != 1 && !corner) {
          const glm::dvec3 origin = randomUnit(rng) * (2.0 + 10.0 * u01(rng));
          // The hit is at t = 1 up to the rounding of t (a few ulps): allow 1e-9.
          EXPECT_TRUE(bvh.occluded(origin, target - origin, 0.0, 1.0 + 1e-9)) << "outside ray " << rays;
        }
        const glm::dvec3 inside = (randomUnit(rng) * 0.5) * u01(rng);
        EXPECT_TRUE(bvh.occluded(inside, target - inside, 0.0, 2.0)) << "inside ray " << rays;
        rays += 2;
      }
  }
  // Axis-aligned rays exactly along the shared diagonal plane and through the centre of a face.
  EXPECT_TRUE(bvh.occluded({0, 0, 5}, {0, 0, -1}, 0.0, 10.0));
  EXPECT_TRUE(bvh.occluded({1, 1, 5}, {0, 0, -1}, 0.0, 10.0));  // straight down a cube edge line
  EXPECT_TRUE(bvh.occluded({0.25, 0.25, 5}, {0, 0, -1}, 0.0, 10.0));
}

TEST(Bvh, AgreesWithBruteForceOnRandomRays) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-10.0, 10.0), u01(0.0, 1.0);
  std::vector<BvhTriangle> tris;
  for (int i = 0; i < 2000; ++i) {
    const glm::dvec3 c(u(rng), u(rng), u(rng));
    const double s = 0.05 + 2.0 * u01(rng);
    tris.push_back({c + s * randomUnit(rng), c + s * randomUnit(rng), c + s * randomUnit(rng)});
  }
  const Bvh bvh(tris);
  int hits = 0;
  for (int r = 0; r < 20000; ++r) {
    const glm::dvec3 o(u(rng), u(rng), u(rng));
    const glm::dvec3 d = randomUnit(rng) * (0.1 + u01(rng));
    const double tMin = 0.001, tMax = u01(rng) < 0.5 ? 1000.0 : 5.0;
    bool brute = false;
    double tBrute = tMax, t;
    for (const auto& tri : bvh.triangles()) {
      if (intersectTriangleWatertight(tri, o, d, tMin, tBrute, t)) {
        brute = true;
        tBrute = t;
      }
    }
    ASSERT_EQ(bvh.occluded(o, d, tMin, tMax), brute) << "ray " << r;
    double tBvh = 0.0;
    ASSERT_EQ(bvh.closestHit(o, d, tMin, tMax, tBvh), brute);
    if (brute) {
      EXPECT_EQ(tBvh, tBrute);  // same triangle test on the same data: bit-identical
    }
    hits += brute;
  }
  EXPECT_GT(hits, 2000);
  EXPECT_LT(hits, 18000);
}

TEST(Bvh, DegenerateTrianglesNeverHitAndProduceNoNaN) {
  const glm::dvec3 a(0, 0, 0), b(1, 0, 0), c(2, 0, 0);
  const std::vector<BvhTriangle> degenerate = {
      {a, b, c},                               // collinear
      {a, a, b},                               // repeated vertex
      {a, a, a},                               // a point
      {a, b, glm::dvec3(0.5, 1e-300, 0)},      // area far below rounding
      {a, b, glm::dvec3(std::nan(""), 0, 0)},  // non-finite
  };
  for (const auto& t : degenerate) {
    EXPECT_TRUE(isDegenerate(t));
    double tHit = -1.0;
    // Rays through the segment, along it, and at its endpoint.
    EXPECT_FALSE(intersectTriangleWatertight(t, {0.5, 0, 1}, {0, 0, -1}, 0.0, 10.0, tHit));
    EXPECT_FALSE(intersectTriangleWatertight(t, {-1, 0, 0}, {1, 0, 0}, 0.0, 10.0, tHit));
    EXPECT_FALSE(intersectTriangleWatertight(t, {0, 0, 1}, {0, 0, -1}, 0.0, 10.0, tHit));
    EXPECT_EQ(tHit, -1.0);
  }
  Bvh bvh(degenerate);
  EXPECT_EQ(bvh.triangleCount(), 0u);
  EXPECT_EQ(bvh.droppedDegenerate(), degenerate.size());
  EXPECT_FALSE(bvh.occluded({0.5, 0, 1}, {0, 0, -1}, 0.0, 10.0));
  // A zero direction never hits a valid triangle either.
  const Bvh cubeBvh(cube());
  EXPECT_FALSE(cubeBvh.occluded({0, 0, 0}, {0, 0, 0}, 0.0, 10.0));
}

TEST(Bvh, RespectsTheRayInterval) {
  const Bvh bvh(cube());
  EXPECT_FALSE(bvh.occluded({0, 0, 5}, {0, 0, -1}, 0.0, 3.9));  // face at t = 4
  EXPECT_TRUE(bvh.occluded({0, 0, 5}, {0, 0, -1}, 0.0, 4.0));   // closed interval
  EXPECT_TRUE(bvh.occluded({0, 0, 5}, {0, 0, -1}, 4.5, 10.0));  // the far face at t = 6
  EXPECT_FALSE(bvh.occluded({0, 0, 5}, {0, 0, -1}, 6.001, 10.0));
}

TEST(Bvh, BuildsFromSceneInstancesAndPrimitives) {
  Scene s;
  for (const auto& t : cube())
    for (const auto& p : {t.v0, t.v1, t.v2}) {
      s.indices.push_back(uint32_t(s.vertices.size()));
      s.vertices.push_back({glm::vec3(p), glm::vec3(0), glm::vec2(0)});
    }
  s.meshes.push_back({"cube", {Primitive{0, uint32_t(s.indices.size()), 0, uint32_t(s.vertices.size()), 0}}});
  Instance a, b;
  b.transform[3] = glm::vec4(10, 0, 0, 1);  // second cube at x = 10
  s.instances = {a, b};
  const Bvh bvh = buildBvh(s);
  EXPECT_EQ(bvh.triangleCount(), 48u);
  EXPECT_TRUE(bvh.occluded({10, 0, 5}, {0, 0, -1}, 0.0, 10.0));
  EXPECT_FALSE(bvh.occluded({5, 0, 5}, {0, 0, -1}, 0.0, 10.0));
}

// ---- which triangle ---------------------------------------------------------------------------------

TEST(Bvh, NamesTheSameNearestTriangleAsABruteForceSearch) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  const std::vector<BvhTriangle> tris = randomTriangles(rng, 300, 5.0, 0.5);
  const Bvh bvh(tris);  // closestHit names the triangle by its index in `tris`
  int hits = 0;
  for (int r = 0; r < 500; ++r) {
    const glm::dvec3 o(u(rng), u(rng), 8.0), target(u(rng), u(rng), u(rng));
    const glm::dvec3 dir = target - o;
    double bestT = std::numeric_limits<double>::infinity();
    int best = -1;
    for (size_t i = 0; i < tris.size(); ++i) {
      double t;
      if (intersectTriangleWatertight(tris[i], o, dir, 0.0, bestT, t)) bestT = t, best = int(i);
    }
    double t;
    uint32_t tri;
    const bool hit = bvh.closestHit(o, dir, 0.0, 1e30, t, tri);
    ASSERT_EQ(hit, best >= 0) << "ray " << r;
    if (!hit) continue;
    ++hits;
    EXPECT_EQ(t, bestT);
    // Ties (two triangles at the same t) may name either; the hit distance must then agree.
    double t2;
    EXPECT_TRUE(intersectTriangleWatertight(tris[tri], o, dir, 0.0, 1e30, t2));
    EXPECT_EQ(t2, bestT);
  }
  EXPECT_GT(hits, 50);  // the test exercised hits, not just misses
}

// ---- every hit along a line ------------------------------------------------------------------------

TEST(Bvh, AllHitsListsEveryTriangleABruteForceSearchHitsInOrder) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-4.0, 4.0);
  const std::vector<BvhTriangle> tris = randomTriangles(rng, 400, 4.0, 0.8);
  const Bvh bvh(tris);
  size_t total = 0;
  std::vector<BvhHit> hits;
  for (int r = 0; r < 1000; ++r) {
    const glm::dvec3 o(u(rng), u(rng), u(rng));
    const glm::dvec3 d = randomUnit(rng);
    const double tMin = r % 2 ? -std::numeric_limits<double>::infinity() : 0.5, tMax = r % 3 ? 3.0 : 1e30;
    std::vector<BvhHit> brute;
    for (uint32_t i = 0; i < tris.size(); ++i) {
      double t;
      if (intersectTriangleWatertight(tris[i], o, d, tMin, tMax, t)) brute.push_back({t, i});
    }
    bvh.allHits(o, d, tMin, tMax, hits);
    ASSERT_EQ(hits.size(), brute.size()) << "ray " << r;
    for (size_t k = 1; k < hits.size(); ++k) ASSERT_LE(hits[k - 1].t, hits[k].t);
    for (const BvhHit& b : brute) {  // same test on the same data: the same t, bit for bit
      const bool found = std::any_of(hits.begin(), hits.end(),
                                     [&](const BvhHit& h) { return h.triangle == b.triangle && h.t == b.t; });
      EXPECT_TRUE(found) << "ray " << r << " triangle " << b.triangle;
    }
    total += hits.size();
  }
  EXPECT_GT(total, 500u);  // many rays met several triangles
}

TEST(Bvh, AllHitsAlongALineThroughAClosedCubeFindBothFaces) {
  const Bvh bvh(cube());
  std::vector<BvhHit> hits;
  bvh.allHits({0.25, 0.1, 5}, {0, 0, -1}, 0.0, 10.0, hits);  // inside one fan triangle per face
  ASSERT_EQ(hits.size(), 2u);
  EXPECT_EQ(hits[0].t, 4.0);
  EXPECT_EQ(hits[1].t, 6.0);
  // The whole line from a point inside: one hit behind (t < 0), one ahead.
  bvh.allHits({0.3, 0.2, 0}, {0, 0, 1}, -std::numeric_limits<double>::infinity(),
              std::numeric_limits<double>::infinity(), hits);
  ASSERT_EQ(hits.size(), 2u);
  EXPECT_EQ(hits[0].t, -1.0);
  EXPECT_EQ(hits[1].t, 1.0);
  // Through the face centres, the shared vertex of each face's fan of 4: every fan triangle hit.
  bvh.allHits({0, 0, 5}, {0, 0, -1}, 0.0, 10.0, hits);
  EXPECT_EQ(hits.size(), 8u);
  bvh.allHits({0.25, 0.1, 5}, {0, 0, -1}, 4.5, 5.5, hits);  // nothing inside the interval
  EXPECT_TRUE(hits.empty());
}

}  // namespace
}  // namespace hb
