#include "reference/ldm_ref.h"
#include "base/numbers.h"
#include "reference/random_unit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

#include "reference/eq_partition.h"
#include "scene/mesh_builder.h"

namespace hb {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Bvh bvhOf(MeshBuilder& mb) {
  Scene s;
  s.materials.push_back({});
  mb.appendTo(s);
  return buildBvh(s);
}

Bvh closedBox(glm::dvec3 lo, glm::dvec3 hi) {
  MeshBuilder mb("box");
  addBox(mb, 0, lo, hi);
  return bvhOf(mb);
}

// Floor [-1, 1]² at z = 0 and four walls up to z = h; no lid.
Bvh openTopBox(double h) {
  MeshBuilder mb("open box");
  addQuad(mb, 0, {-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, {0, 0, 1});
  addQuad(mb, 0, {-1, -1, 0}, {-1, 1, 0}, {-1, 1, h}, {-1, -1, h}, {1, 0, 0});
  addQuad(mb, 0, {1, -1, 0}, {1, 1, 0}, {1, 1, h}, {1, -1, h}, {-1, 0, 0});
  addQuad(mb, 0, {-1, -1, 0}, {1, -1, 0}, {1, -1, h}, {-1, -1, h}, {0, 1, 0});
  addQuad(mb, 0, {-1, 1, 0}, {1, 1, 0}, {1, 1, h}, {-1, 1, h}, {0, -1, 0});
  return bvhOf(mb);
}

std::vector<LdmView> viewsFor(const std::vector<glm::dvec3>& dirs, const LdmSphere& s, uint32_t resolution) {
  std::vector<LdmView> views;
  for (const auto& d : dirs) views.push_back(ldmView(d, s.centre, s.radius, resolution));
  return views;
}

// Entry and exit of the line o + t d through the box [lo, hi] (slabs); false when it misses.
bool slab(glm::dvec3 lo, glm::dvec3 hi, glm::dvec3 o, glm::dvec3 d, double& t0, double& t1) {
  t0 = -kInf, t1 = kInf;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (o[a] < lo[a] || o[a] > hi[a]) return false;
      continue;
    }
    double n = (lo[a] - o[a]) / d[a], f = (hi[a] - o[a]) / d[a];
    if (n > f) std::swap(n, f);
    t0 = std::max(t0, n), t1 = std::min(t1, f);
  }
  return t0 < t1;
}

// ---- view, basis, pixels ---------------------------------------------------------------------------

TEST(LdmView, BasisIsRightHandedOrthonormalWithRightCrossUpAlongMinusDir) {
  std::mt19937_64 rng(21);
  std::vector<glm::dvec3> dirs = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0},       {-1, 0, 0},
                                  {0, 1, 0}, {0, -1, 0}, {0.6, 0.8, 0.0}, {0.6, 0.8, -0.0}};
  for (int k = 0; k < 2000; ++k) dirs.push_back(randomUnit(rng));
  for (const auto& d : ldmDirections(512)) dirs.push_back(d);
  for (const auto& d : dirs) {
    const LdmView v = ldmView(d, {0, 0, 0}, 1.0, 8);
    // Each component is a few multiplications of numbers <= 1: errors of a few ulps, < 1e-15.
    EXPECT_NEAR(glm::length(v.right), 1.0, 1e-15);
    EXPECT_NEAR(glm::length(v.up), 1.0, 1e-15);
    EXPECT_NEAR(glm::dot(v.right, v.up), 0.0, 1e-15);
    EXPECT_NEAR(glm::dot(v.right, d), 0.0, 1e-15);
    EXPECT_NEAR(glm::length(glm::cross(v.right, v.up) + d), 0.0, 2e-15);
  }
  // Looking down -z (as view space does): right = +x, up = +y, exactly.
  const LdmView v = ldmView({0, 0, -1}, {0, 0, 0}, 1.0, 8);
  EXPECT_EQ(v.right, glm::dvec3(1, 0, 0));
  EXPECT_EQ(v.up, glm::dvec3(0, 1, 0));
}

TEST(LdmView, PixelLinesProjectBackToTheirPixelAtEveryDepth) {
  std::mt19937_64 rng(22);
  for (int k = 0; k < 20; ++k) {
    const LdmView v = ldmView(randomUnit(rng), {0.5, -2.0, 3.0}, 2.5, 37);
    for (uint32_t j = 0; j < 37; ++j)
      for (uint32_t i = 0; i < 37; ++i) {
        const glm::dvec3 o = ldmPixelOrigin(v, i, j);
        EXPECT_NEAR(ldmDepth(v, o), 0.0, 1e-14);  // a few ulps of the coordinates (~5)
        for (double z : {0.0, 1.0, 4.99}) {
          uint32_t pi = 99, pj = 99;
          ASSERT_TRUE(ldmProject(v, o + z * v.dir, pi, pj));
          EXPECT_EQ(pi, i);  // the centre is half a pixel from either border: floor is exact
          EXPECT_EQ(pj, j);
          EXPECT_NEAR(ldmDepth(v, o + z * v.dir), z, 1e-14);
        }
      }
    uint32_t i, j;
    // The map covers the square [-radius, radius]² about the centre; i grows right, j grows down.
    ASSERT_TRUE(ldmProject(v, v.centre + 2.4 * (v.up - v.right), i, j));
    EXPECT_EQ(i, 0u);
    EXPECT_EQ(j, 0u);
    ASSERT_TRUE(ldmProject(v, v.centre + 2.4 * (v.right - v.up), i, j));
    EXPECT_EQ(i, 36u);
    EXPECT_EQ(j, 36u);
    EXPECT_FALSE(ldmProject(v, v.centre + 2.6 * v.right, i, j));
    EXPECT_FALSE(ldmProject(v, v.centre - 2.6 * v.up, i, j));
  }
}

// ---- exact LDMs --------------------------------------------------------------------------------

TEST(ExactLdm, ABoxGivesTwoSortedEntriesPerPixelThroughItAndNoneOutside) {
  const glm::dvec3 lo(-0.75, -0.75, -0.25), hi(0.75, 0.75, 0.5);  // exact in float
  const Bvh bvh = closedBox(lo, hi);
  std::mt19937_64 rng(23);
  std::vector<glm::dvec3> dirs = {{0, 0, -1}, {1, 0, 0}, {0, 1, 0}};
  for (int k = 0; k < 6; ++k) dirs.push_back(randomUnit(rng));
  int inside = 0, outside = 0, borderline = 0, onDiagonal = 0;
  for (const auto& d : dirs) {
    // Sphere centre 0, radius 1.5: pixel centres are dyadic along the axes (spacing 3/64), so
    // looking down -z those with i + j = 63 lie exactly on the top and bottom faces' diagonal
    // x = y, and none on a silhouette edge (±0.75 is no pixel centre).
    const LdmView view = ldmView(d, {0, 0, 0}, 1.5, 64);
    const ExactLdm ldm = exactLdm(bvh, view);
    ASSERT_EQ(ldm.first.size(), 64u * 64u + 1u);
    for (uint32_t j = 0; j < 64; ++j)
      for (uint32_t i = 0; i < 64; ++i) {
        const auto list = ldm.pixel(i, j);
        EXPECT_TRUE(std::is_sorted(list.begin(), list.end()));
        EXPECT_EQ(list.size() % 2, 0u) << "a line crosses a closed surface an even number of times";
        const glm::dvec3 o = ldmPixelOrigin(view, i, j);
        std::vector<BvhHit> raw;
        bvh.allHits(o, d, 0.0, 3.0, raw);
        onDiagonal += raw.size() > list.size();
        // Robust cases: the line and its shifts by 1e-6 in right and up all hit or all miss.
        double t0, t1, s0, s1;
        const bool hit = slab(lo, hi, o, d, t0, t1);
        bool same = true;
        for (const glm::dvec3 e : {view.right, -view.right, view.up, -view.up})
          same = same && slab(lo, hi, o + 1e-6 * e, d, s0, s1) == hit;
        if (!same) {
          ++borderline;
        } else if (hit) {
          ++inside;
          ASSERT_EQ(list.size(), 2u) << "pixel " << i << "," << j;
          // Slab and watertight t are each a few ulps of coordinates <= 3: |error| < 1e-14.
          EXPECT_NEAR(list[0], t0, 1e-12);
          EXPECT_NEAR(list[1], t1, 1e-12);
        } else {
          ++outside;
          EXPECT_EQ(list.size(), 0u) << "pixel " << i << "," << j;
        }
      }
  }
  EXPECT_GT(inside, 5000);
  EXPECT_GT(outside, 5000);
  EXPECT_LT(borderline, 200);  // pixels within 1e-6 of the silhouette: a few per view at most
  EXPECT_GT(onDiagonal, 0);    // the merge of hits through a shared edge was exercised
  std::printf("[ exact ldm ] box: %d pixels through, %d outside, %d borderline, %d on a shared edge\n", inside, outside,
              borderline, onDiagonal);
}

TEST(ExactLdm, NodeStatsOfTwoBoxesBehindEachOther) {
  MeshBuilder mb("two boxes");
  addBox(mb, 0, {-0.5, -0.5, -1.0}, {0.5, 0.5, -0.5});
  addBox(mb, 0, {-0.25, -0.25, 0.5}, {0.25, 0.25, 1.0});
  const Bvh bvh = bvhOf(mb);
  const LdmSphere s = ldmBoundingSphere(bvh);
  const ExactLdm ldm = exactLdm(bvh, ldmView({0, 0, -1}, s.centre, s.radius, 128));
  const LdmNodeStats st = ldmNodeStats(ldm);
  EXPECT_EQ(st.pixels, 128u * 128u);
  EXPECT_EQ(st.max, 4u);  // through both boxes
  // Covered fractions of the (2r)² map: 1 m² (2 entries) and 0.25 m² of it (2 more):
  // mean = (2·1 + 2·0.25)/(2r)², up to the pixels along the 8 silhouette edges
  // (~perimeter/pixel = 6 m / (2r/128) pixels of 1/128² of the area each): within 2 %.
  const double expected = 2.5 / (4.0 * s.radius * s.radius);
  EXPECT_NEAR(st.mean, expected, 0.02 * expected);
  EXPECT_EQ(st.p99, 4u);  // 0.25/(2r)² = 5.6 % of the pixels hold 4
  std::printf("[ exact ldm ] two boxes, 128²: nodes per pixel mean %.4f (expected %.4f), p99 %u, max %u\n", st.mean,
              expected, st.p99, st.max);
}

TEST(ExactLdm, AClosedSphereHasEvenListsOfAtMostTwo) {
  MeshBuilder mb("sphere");
  addSphere(mb, 0, glm::dmat4(1.0), 48, 24);
  const Bvh bvh = bvhOf(mb);
  const LdmSphere s = ldmBoundingSphere(bvh);
  std::mt19937_64 rng(24);
  for (int k = 0; k < 4; ++k) {
    const ExactLdm ldm = exactLdm(bvh, ldmView(randomUnit(rng), s.centre, s.radius, 96));
    for (uint32_t px = 0; px + 1 < ldm.first.size(); ++px) {
      const uint32_t n = ldm.first[px + 1] - ldm.first[px];
      EXPECT_TRUE(n == 0 || n == 2) << n;  // convex and closed: in and out
    }
    const LdmNodeStats st = ldmNodeStats(ldm);
    // Projected area <= π (the polygon lies inside the unit sphere), >= π cos²(π/24) roughly.
    EXPECT_LE(st.mean, 2.0 * kPi / (4.0 * s.radius * s.radius) * 1.02);
    EXPECT_GE(st.mean, 2.0 * kPi / (4.0 * s.radius * s.radius) * 0.95);
  }
}

// ---- trace ----------------------------------------------------------------------------------------

TEST(LdmTrace, ForwardIsTheFirstEntryAboveAndBackwardTheLastBelowBeyondTheBias) {
  const std::vector<double> l = {1.0, 2.0, 3.0, 3.0005, 5.0};
  auto t = ldmTraceList(l, 3.0, 0.001);  // x on the surface at 3 (and 3.0005 within the bias)
  EXPECT_TRUE(t.forward.hit);
  EXPECT_DOUBLE_EQ(t.forward.distance, 2.0);
  EXPECT_TRUE(t.backward.hit);
  EXPECT_DOUBLE_EQ(t.backward.distance, 1.0);
  t = ldmTraceList(l, 2.5, 0.0);  // between entries: both neighbours
  EXPECT_DOUBLE_EQ(t.forward.distance, 0.5);
  EXPECT_DOUBLE_EQ(t.backward.distance, 0.5);
  t = ldmTraceList(l, 0.5, 0.0);  // in front of everything
  EXPECT_FALSE(t.backward.hit);
  EXPECT_DOUBLE_EQ(t.forward.distance, 0.5);
  t = ldmTraceList(l, 5.0, 0.01);  // on the last surface
  EXPECT_FALSE(t.forward.hit);
  EXPECT_DOUBLE_EQ(t.backward.distance, 5.0 - 3.0005);
  t = ldmTraceList({}, 1.0, 0.0);
  EXPECT_FALSE(t.forward.hit);
  EXPECT_FALSE(t.backward.hit);
}

TEST(LdmTrace, OnAPixelLineMatchesTheRayCastBothWays) {
  const Bvh bvh = closedBox({-1, -1, -1}, {1, 1, 1});
  const LdmSphere s = ldmBoundingSphere(bvh);
  std::mt19937_64 rng(25);
  std::uniform_int_distribution<uint32_t> pix(20, 43);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < 20; ++k) {
    const ExactLdm ldm = exactLdm(bvh, ldmView(randomUnit(rng), s.centre, s.radius, 64));
    const uint32_t i = pix(rng), j = pix(rng);  // central pixels: their lines cross the box
    const auto list = ldm.pixel(i, j);
    ASSERT_EQ(list.size(), 2u);
    // x on the pixel's line, inside the box: the trace and the ray cast see the same faces.
    const glm::dvec3 x = ldmPixelOrigin(ldm.view, i, j) + (list[0] + u(rng) * (list[1] - list[0])) * ldm.view.dir;
    const LdmTrace tr = ldmTrace(ldm, x, 1e-9);
    double tf, tb;
    ASSERT_TRUE(bvh.closestHit(x, ldm.view.dir, 0.0, 10.0, tf));
    ASSERT_TRUE(bvh.closestHit(x, -ldm.view.dir, 0.0, 10.0, tb));
    ASSERT_TRUE(tr.forward.hit && tr.backward.hit);
    EXPECT_NEAR(tr.forward.distance, tf, 1e-12);  // same line, t to a few ulps of 3
    EXPECT_NEAR(tr.backward.distance, tb, 1e-12);
  }
  // A point outside the map sees nothing.
  const ExactLdm ldm = exactLdm(bvh, ldmView({0, 0, 1}, s.centre, s.radius, 8));
  const LdmTrace tr = ldmTrace(ldm, s.centre + glm::dvec3(3 * s.radius, 0, 0), 0.0);
  EXPECT_FALSE(tr.forward.hit || tr.backward.hit);
}

// ---- ambient occlusion ----------------------------------------------------------------------------

TEST(Ao, OpenSkyAboveAGroundPlaneIsTheCosineSumAndMonteCarloIsExactlyOne) {
  // A tilted ground plane (the pole axis is the directions' worst normal, 1.27 % at N = 64; see
  // eq_partition_test), p 1 m above it, n its normal.
  const glm::dvec3 n = glm::normalize(glm::dvec3(1, 2, 5));
  glm::dvec3 t, b;
  orthonormalBasis(n, t, b);
  MeshBuilder mb("ground");
  addQuad(mb, 0, -50.0 * t - 50.0 * b, 50.0 * t - 50.0 * b, 50.0 * t + 50.0 * b, -50.0 * t + 50.0 * b, n);
  const Bvh bvh = bvhOf(mb);
  const glm::dvec3 p = 0.3 * t - 0.2 * b + 1.0 * n;
  for (uint32_t count : {64u, 256u}) {
    const auto dirs = ldmDirections(count);
    double sum = 0.0;
    for (const auto& v : dirs)
      if (glm::dot(n, v) != 0.0) sum += std::abs(glm::dot(n, v));
    const double cosineSum = 2.0 * sum / double(count);
    const double rt = aoRayTraced(bvh, p, n, dirs, kInf, 1e-4);
    EXPECT_EQ(rt, cosineSum);  // nothing occluded: the same terms in the same order
    EXPECT_NEAR(rt, 1.0, count == 64 ? 0.012 : 0.003);
    const LdmSphere s = ldmBoundingSphere(bvh);
    EXPECT_EQ(aoLdm(bvh, viewsFor(dirs, s, 1024), p, n, kInf, 1e-4), rt);
    std::printf("[ ao ] open sky, N = %u: ray traced %.5f\n", count, rt);
  }
  EXPECT_EQ(aoMonteCarlo(bvh, p, n, 1024, 7, kInf, 1e-4), 1.0);
  EXPECT_THROW(aoMonteCarlo(bvh, p, n, 1000, 7, kInf, 1e-4), std::invalid_argument);
}

TEST(Ao, IsZeroEverywhereInsideAClosedBoxAndTheObscuranceCutSeesNothingNearby) {
  const Bvh bvh = closedBox({-1, -1, -1}, {1, 1, 1});
  const LdmSphere s = ldmBoundingSphere(bvh);
  const auto dirs16 = ldmDirections(16), dirs64 = ldmDirections(64);
  std::vector<ExactLdm> maps;
  for (const auto& v : viewsFor(dirs16, s, 64)) maps.push_back(exactLdm(bvh, v));
  std::mt19937_64 rng(26);
  std::uniform_real_distribution<double> u(-0.25, 0.25);
  for (int k = 0; k < 10; ++k) {
    const glm::dvec3 p(u(rng), u(rng), u(rng)), n = randomUnit(rng);
    EXPECT_EQ(aoRayTraced(bvh, p, n, dirs64, kInf, 1e-4), 0.0);
    EXPECT_EQ(aoMonteCarlo(bvh, p, n, 256, 11 + k, kInf, 1e-4), 0.0);
    EXPECT_EQ(aoLdm(maps, p, n, kInf, 1e-4), 0.0);
    EXPECT_EQ(aoLdm(bvh, viewsFor(dirs64, s, 256), p, n, kInf, 1e-4), 0.0);
    // Walls are >= 0.75 away: a 0.5 m obscurance radius sees open sky.
    double sum = 0.0;
    for (const auto& v : dirs64)
      if (glm::dot(n, v) != 0.0) sum += std::abs(glm::dot(n, v));
    EXPECT_EQ(aoRayTraced(bvh, p, n, dirs64, 0.5, 1e-4), 2.0 * sum / 64.0);
    EXPECT_EQ(aoLdm(bvh, viewsFor(dirs64, s, 256), p, n, 0.5, 1e-4), 2.0 * sum / 64.0);
    EXPECT_EQ(aoMonteCarlo(bvh, p, n, 256, 11 + k, 0.5, 1e-4), 1.0);
    // The full maps and the per-pixel path read the same lists.
    const glm::dvec3 q(u(rng), u(rng), u(rng));
    EXPECT_EQ(aoLdm(maps, q, n, 1.0, 1e-4), aoLdm(bvh, viewsFor(dirs16, s, 64), q, n, 1.0, 1e-4));
  }
}

// ---- the open-top box: analytic AO, quadrature and Monte Carlo errors, LDM agreement ---------------

// View factor from a floor point to a parallel a × b rectangle at height c with one corner
// straight above it (Howell's catalogue, configuration B-3):
//   F = (1/2π) [A/√(1+A²) atan(B/√(1+A²)) + B/√(1+B²) atan(A/√(1+B²))],  A = a/c, B = b/c.
double cornerViewFactor(double a, double b, double c) {
  const double A = a / c, B = b / c, sa = std::sqrt(1 + A * A), sb = std::sqrt(1 + B * B);
  return (A / sa * std::atan(B / sa) + B / sb * std::atan(A / sb)) / (2.0 * kPi);
}

// AO at (x, y, 0) on the floor of openTopBox(h), n = +z: the opening's view factor, as four
// rectangles with a corner above the point.
double openBoxAo(double x, double y, double h) {
  return cornerViewFactor(1 - x, 1 - y, h) + cornerViewFactor(1 + x, 1 - y, h) + cornerViewFactor(1 - x, 1 + y, h) +
         cornerViewFactor(1 + x, 1 + y, h);
}

// Whether direction w from (x, y, 0) leaves through the opening (else a wall or the floor stops it).
bool throughOpening(double x, double y, double h, const glm::dvec3& w) {
  if (!(w.z > 0.0)) return false;
  const double s = h / w.z;
  return std::abs(x + s * w.x) <= 1.0 && std::abs(y + s * w.y) <= 1.0;
}

// Error model of aoRayTraced against the exact integral, n = +z. The sum is a quadrature over the
// regions of EQ(2, 2N) in the upper hemisphere (the equator ring's upper halves carry weight 0).
// Per region, exact part E = (1/π)∫ cos = (Δφ/2π)(sin² bottom' - sin² top), bottom' = min(bottom, π/2),
// term w = (2/N) cos(centre) V(centre):
//  - fully visible: error w - E, deterministic (the cosine's midpoint error), summed exactly;
//  - fully hidden: error 0;
//  - crossed by the opening's outline: error w·V(centre) - E·φ, φ the visible fraction. An
//    outline that is straight across the region at an offset u ~ U(-1/2, 1/2) of its width gives
//    φ = 1/2 + u and V = [u > 0], so with w ≈ E = a the error a([u > 0] - 1/2 - u) is uniform on
//    [-a/2, a/2]: variance a²/12, a = (w + E)/2. Regions are taken as independent (where the
//    outline cuts one is unrelated to where it cuts the next). The worst case (a region off by its
//    whole weight) would be 3.5 times larger; over 48 points the measured rms matches this σ.
// Full/hidden/crossed is decided on a 16×16 grid of (θ, φ) per region.
struct ErrorModel {
  double deterministic = 0.0, sigma = 0.0;
  int crossed = 0;
};
ErrorModel quadratureModel(double x, double y, double h, uint32_t n) {
  ErrorModel m;
  double variance = 0.0;
  for (const EqRegion& r : eqRegions(2 * n)) {
    if (r.top >= kPi / 2) continue;
    const double bottom = std::min(r.bottom, kPi / 2);
    const double sb = std::sin(bottom), st = std::sin(r.top);
    const double exact = (r.lonHi - r.lonLo) / (2 * kPi) * (sb * sb - st * st);
    const double w = r.colatitude < kPi / 2 - 1e-12 ? 2.0 / n * std::cos(r.colatitude) : 0.0;
    int seen = 0;
    for (int a = 0; a < 16; ++a)
      for (int b = 0; b < 16; ++b) {
        const double th = r.top + (a + 0.5) / 16 * (bottom - r.top);
        const double ph = r.lonLo + (b + 0.5) / 16 * (r.lonHi - r.lonLo);
        seen += throughOpening(x, y, h, {std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)});
      }
    if (seen == 256) {
      m.deterministic += w - exact;
    } else if (seen > 0) {
      ++m.crossed;
      variance += (w + exact) * (w + exact) / 48;
    }
  }
  m.sigma = std::sqrt(variance);
  return m;
}

// Error model of aoMonteCarlo: every stratum has probability 1/S (the concentric map and Malley's
// lift preserve measure), so only strata the outline crosses err, each by (V - p_k)/S with variance
// <= 1/(4S²): σ <= √K/(2S). Crossing decided on an 8×8 grid per stratum.
ErrorModel monteCarloModel(double x, double y, double h, uint32_t samples) {
  const uint32_t k = uint32_t(std::lround(std::sqrt(double(samples))));
  ErrorModel m;
  for (uint32_t sb = 0; sb < k; ++sb)
    for (uint32_t sa = 0; sa < k; ++sa) {
      int seen = 0;
      for (int a = 0; a < 8; ++a)
        for (int b = 0; b < 8; ++b)
          seen += throughOpening(
              x, y, h, cosineHemisphereDirection((sa + (a + 0.5) / 8) / k, (sb + (b + 0.5) / 8) / k, {0, 0, 1}));
      m.crossed += seen > 0 && seen < 64;
    }
  m.sigma = std::sqrt(double(m.crossed)) / (2.0 * samples);
  return m;
}

const glm::dvec2 kFloorPoints[] = {{0, 0}, {0.4, -0.3}, {-0.6, 0.5}, {0.75, 0.75}};

TEST(Ao, RayTracedAndMonteCarloMatchTheOpeningsViewFactorOnTheFloorOfAnOpenBox) {
  const double h = 1.0, tMin = 0.01;
  const Bvh bvh = openTopBox(h);
  const auto dirs = ldmDirections(256);
  for (const glm::dvec2 f : kFloorPoints) {
    const glm::dvec3 p(f.x, f.y, 0.0), n(0, 0, 1);
    const double exact = openBoxAo(f.x, f.y, h);
    const double rt = aoRayTraced(bvh, p, n, dirs, kInf, tMin);
    const double mc = aoMonteCarlo(bvh, p, n, 1024, 1234, kInf, tMin);
    const ErrorModel q = quadratureModel(f.x, f.y, h, 256), s = monteCarloModel(f.x, f.y, h, 1024);
    // 5σ: a normal tail of 6e-7 (the seeds are fixed; the bound says how far off is explicable).
    const double tolRt = std::abs(q.deterministic) + 5 * q.sigma, tolMc = 5 * s.sigma;
    EXPECT_NEAR(rt, exact, tolRt) << f.x << "," << f.y;
    EXPECT_NEAR(mc, exact, tolMc) << f.x << "," << f.y;
    EXPECT_NEAR(rt, mc, tolRt + tolMc) << f.x << "," << f.y;
    std::printf(
        "[ ao ] open box at (%5.2f,%5.2f): exact %.5f  ray traced N=256 %.5f (err %+.5f, tol %.4f = "
        "%.5f + 5x%.5f, %d regions crossed)  MC 1024 %.5f (err %+.5f, tol %.4f, %d strata crossed)\n",
        f.x, f.y, exact, rt, rt - exact, tolRt, std::abs(q.deterministic), q.sigma, q.crossed, mc, mc - exact, tolMc,
        s.crossed);
  }
}

TEST(Ao, RayTracedErrorOverManyFloorPointsStaysWithinTheQuadratureModel) {
  // Over many points the errors must be unbiased and of the model's size: rms within 2σ (the
  // model is approximate: corners of the outline, neighbouring regions cut by one straight edge),
  // |mean| within 5σ/√P (points share the direction set, so this is a check, not a theorem).
  const double h = 1.0;
  const Bvh bvh = openTopBox(h);
  const auto dirs = ldmDirections(256);
  std::mt19937_64 rng(27);
  std::uniform_real_distribution<double> u(-0.8, 0.8);
  constexpr int kPoints = 48;
  double sumErr = 0.0, sumSq = 0.0, sumVar = 0.0, maxDet = 0.0;
  for (int k = 0; k < kPoints; ++k) {
    const double x = u(rng), y = u(rng);
    const double e = aoRayTraced(bvh, {x, y, 0.0}, {0, 0, 1}, dirs, kInf, 0.01) - openBoxAo(x, y, h);
    const ErrorModel q = quadratureModel(x, y, h, 256);
    sumErr += e, sumSq += e * e, sumVar += q.sigma * q.sigma;
    maxDet = std::max(maxDet, std::abs(q.deterministic));
  }
  const double mean = sumErr / kPoints, rms = std::sqrt(sumSq / kPoints), sigma = std::sqrt(sumVar / kPoints);
  std::printf("[ ao ] open box, ray traced N=256 over %d floor points: mean error %+.5f, rms %.5f (model sigma %.5f)\n",
              kPoints, mean, rms, sigma);
  EXPECT_LE(rms, 2.0 * sigma + maxDet);
  EXPECT_LE(std::abs(mean), 5.0 * sigma / std::sqrt(double(kPoints)) + maxDet);
}

// Distance from the line p + t w (w unit) to the segment [a, b]: the component perpendicular to w
// is affine along the segment; its smallest length on [0, 1].
double lineSegmentDistance(const glm::dvec3& p, const glm::dvec3& w, const glm::dvec3& a, const glm::dvec3& b) {
  const auto perp = [&](const glm::dvec3& v) { return v - glm::dot(v, w) * w; };
  const glm::dvec3 f0 = perp(a - p), f1 = perp(b - a);
  const double ff = glm::dot(f1, f1);
  const double s = ff > 0.0 ? std::clamp(-glm::dot(f0, f1) / ff, 0.0, 1.0) : 0.0;
  return glm::length(f0 + s * f1);
}

// When does the LDM's V equal the ray's? Pixel (i, j)'s line is p's line moved by δ ⊥ v with
// |δ| <= d = √2·radius/R (half a pixel diagonal). For p on the floor and the direction w = ±v in
// n = +z's hemisphere, the line's forward part (depth > z_x + bias) meets:
//  (a) the floor, at depth z_x - δ_z/w_z: |δ_z| <= d sin θ, so it lies within d·tan θ of z_x
//      (θ between v and n), skipped by the bias unless d·tan θ > bias;
//  (b) the walls exactly when the ray does, unless the line crosses the outline of the walls
//      (their top edges, the rim) as δ varies: only if the ray's line passes within d of a rim
//      edge. (Crossing between two walls at a corner keeps V = 0. A wall is never met before the
//      bias: the line starts inside the box when p is more than d + bias from every wall.)
// So V differs only for directions flagged by (a) or (b), and |aoLdm - aoRayTraced| is at most
// (2/N) Σ_flagged |n·v|. With no flagged direction the two are equal, bit for bit.
TEST(Ao, LdmAgreesWithRayTracingExceptWherePixelSizeOrBiasExplainIt) {
  const double h = 1.0, bias = 0.01;
  const Bvh bvh = openTopBox(h);
  const LdmSphere sphere = ldmBoundingSphere(bvh);
  const auto dirs = ldmDirections(256);
  const glm::dvec3 rim[4][2] = {
      {{-1, -1, h}, {1, -1, h}}, {{1, -1, h}, {1, 1, h}}, {{1, 1, h}, {-1, 1, h}}, {{-1, 1, h}, {-1, -1, h}}};
  const glm::dvec3 n(0, 0, 1);
  for (uint32_t res : {64u, 512u, 4096u}) {
    const double d = std::sqrt(2.0) * sphere.radius / res;
    const auto views = viewsFor(dirs, sphere, res);
    int differ = 0, flaggedCount = 0;
    double worstGap = 0.0;
    for (const glm::dvec2 f : kFloorPoints) {
      const glm::dvec3 p(f.x, f.y, 0.0);
      double flaggedWeight = 0.0;
      for (size_t k = 0; k < dirs.size(); ++k) {
        const double c = glm::dot(n, dirs[k]);
        if (c == 0.0) continue;
        const glm::dvec3 w = c > 0 ? dirs[k] : -dirs[k];
        const bool vRay = aoRayTraced(bvh, p, n, {dirs[k]}, kInf, bias) != 0.0;
        const bool vLdm = aoLdm(bvh, {views[k]}, p, n, kInf, bias) != 0.0;
        const double tanTheta = std::sqrt(std::max(0.0, 1.0 - c * c)) / std::abs(c);
        bool nearRim = false;
        for (const auto& e : rim) nearRim = nearRim || lineSegmentDistance(p, w, e[0], e[1]) <= d;
        const bool flagged = d * tanTheta > bias || nearRim;
        flaggedCount += flagged;
        if (flagged) flaggedWeight += 2.0 / dirs.size() * std::abs(c);
        if (vRay != vLdm) {
          ++differ;
          EXPECT_TRUE(flagged) << "R " << res << " point " << f.x << "," << f.y << " direction " << k;
        }
      }
      const double rt = aoRayTraced(bvh, p, n, dirs, kInf, bias), ldm = aoLdm(bvh, views, p, n, kInf, bias);
      EXPECT_LE(std::abs(ldm - rt), flaggedWeight);
      if (flaggedWeight == 0.0) {
        EXPECT_EQ(ldm, rt);
      }
      worstGap = std::max(worstGap, std::abs(ldm - rt));
    }
    std::printf(
        "[ ao ] LDM vs ray traced, N=256, R=%u: %d of %zu direction tests differ, %d flagged, "
        "worst |AO gap| %.5f\n",
        res, differ, 4 * dirs.size(), flaggedCount, worstGap);
    if (res == 4096) {
      EXPECT_EQ(differ, 0);
    }
  }
}

}  // namespace
}  // namespace hb
