// 3D rasterization reference: the float arithmetic and its derived error bounds, the exact
// fallback, degenerate and eye-plane cases, and agreement with the double-precision ray cast.
// (The fill-rule tests are in raster3d_ref_test.cpp.) Fixed seeds throughout.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <random>
#include <vector>

#include "base/numbers.h"
#include "reference/raster3d_ref.h"
#include "reference/raster3d_ref_test_util.h"

namespace hb {
namespace {

using raster3d_test::randomView;
using raster3d_test::rayAt;

double gamma(int k) { return k * kU / (1.0 - k * kU); }

// Rounded after every operation, whatever the compiler's contraction setting.
float mulR(float a, float b) {
  volatile float p = a * b;
  return p;
}
float addR(float a, float b) {
  volatile float s = a + b;
  return s;
}
float dotR(glm::vec3 a, glm::vec3 b) { return addR(addR(mulR(a.x, b.x), mulR(a.y, b.y)), mulR(a.z, b.z)); }
float edgeR(const Raster3dTriangle& t, int i, uint32_t x, uint32_t y) {
  return addR(addR(t.rowA[i], mulR(float(x), t.rowB[i])), mulR(float(y), t.rowC[i]));
}

glm::vec3 randomVertex(std::mt19937& rng, const Raster3dView& v) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  return glm::vec3(glm::dvec3(v.eye) + (2.0 + 8.0 * u(rng)) * rayAt(v, v.width * u(rng), v.height * u(rng)) +
                   glm::dvec3(u(rng), u(rng), u(rng)) * 0.5);
}

TEST(Raster3dNumerics, SharedEdgeRowsAndBoundsAreBitwiseNegations) {
  std::mt19937 rng(3);
  const Raster3dView v = randomView(rng, 256, 256);
  Raster3dRefCounters c;
  for (int k = 0; k < 2000; ++k) {
    const glm::vec3 a = randomVertex(rng, v), b = randomVertex(rng, v), p = randomVertex(rng, v),
                    q = randomVertex(rng, v);
    Raster3dTriangle t1, t2;  // (a, b, p) and (b, a, q): edge 2 of t1 is a→b... edge 2 of t2 is b→a
    ASSERT_TRUE(setupTriangle3d(v, a, b, p, t1, c) && setupTriangle3d(v, b, a, q, t2, c));
    const float o = float(t1.orientation * t2.orientation);
    EXPECT_EQ(t1.rowA[2], -o * t2.rowA[2]);
    EXPECT_EQ(t1.rowB[2], -o * t2.rowB[2]);
    EXPECT_EQ(t1.rowC[2], -o * t2.rowC[2]);
    EXPECT_EQ(t1.errA[2], t2.errA[2]);
    EXPECT_EQ(t1.tieSign[2], -t1.orientation * t2.orientation * t2.tieSign[2]);
  }
}

// The rows and the per-pixel values are what a GPU computes with `precise` (no fma), bit for bit.
TEST(Raster3dNumerics, RowsAndEdgeValuesAreRoundedAfterEveryOperation) {
  std::mt19937 rng(4);
  const Raster3dView v = randomView(rng, 256, 256);
  Raster3dRefCounters c;
  int covered = 0;
  for (int k = 0; k < 2000; ++k) {
    Raster3dTriangle t;
    ASSERT_TRUE(setupTriangle3d(v, randomVertex(rng, v), randomVertex(rng, v), randomVertex(rng, v), t, c));
    for (int i = 0; i < 3; ++i) {
      const glm::vec3 a = t.p[(i + 1) % 3], b = t.p[(i + 2) % 3];
      const glm::vec3 m(mulR(addR(a.x, b.x), 0.5f), mulR(addR(a.y, b.y), 0.5f), mulR(addR(a.z, b.z), 0.5f));
      const glm::vec3 e = a - b;
      const glm::vec3 n(addR(mulR(m.y, e.z), -mulR(m.z, e.y)), addR(mulR(m.z, e.x), -mulR(m.x, e.z)),
                        addR(mulR(m.x, e.y), -mulR(m.y, e.x)));
      EXPECT_EQ(t.rowA[i], float(t.orientation) * dotR(n, v.d0));
      EXPECT_EQ(t.rowB[i], float(t.orientation) * dotR(n, v.dx));
    }
    for (uint32_t y = 0; y < v.height; y += 17)
      for (uint32_t x = 0; x < v.width; x += 13) {
        float depth;
        glm::vec3 lambda;
        if (!coversPixel3d(v, t, x, y, true, depth, lambda, c)) continue;
        ++covered;
        const glm::vec3 e(edgeR(t, 0, x, y), edgeR(t, 1, x, y), edgeR(t, 2, x, y));
        EXPECT_EQ(lambda, e / addR(addR(e.x, e.y), e.z));
      }
  }
  EXPECT_GT(covered, 1000);
}

// |V_float − V*| <= kEdgeBoundFactor·(errA + x·errB + y·errC) and |V_double − V*| <= its bound,
// with V* = (b × a)·(d0 + x·dx + y·dy) of the float inputs in long double (64-bit significand:
// its error, ~2^-62 of the terms, is negligible against the bounds' 2^-20 and 2^-49).
TEST(Raster3dNumerics, FloatAndDoubleEdgeErrorsStayWithinTheDerivedBounds) {
  if (std::numeric_limits<long double>::digits < 64) GTEST_SKIP() << "needs x87 long double";
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worstF = 0, worstD = 0;
  Raster3dRefCounters c;
  for (int k = 0; k < 4000; ++k) {
    const Raster3dView v = randomView(rng, 512, 512);
    // A vertex on a pixel centre's ray puts two edges through (almost) that centre: V* ~ rounding.
    const uint32_t px = uint32_t(512 * u(rng)), py = uint32_t(512 * u(rng));
    glm::vec3 w0 = glm::vec3(glm::dvec3(v.eye) + (1.0 + 9.0 * u(rng)) * rayAt(v, px, py));
    Raster3dTriangle t;
    if (!setupTriangle3d(v, w0, randomVertex(rng, v), randomVertex(rng, v), t, c)) continue;
    for (int s = 0; s < 8; ++s) {
      const uint32_t x = s == 0 ? px : uint32_t(512 * u(rng)), y = s == 0 ? py : uint32_t(512 * u(rng));
      for (int i = 0; i < 3; ++i) {
        const glm::vec3 a = t.p[(i + 1) % 3], b = t.p[(i + 2) % 3];
        long double exact = 0;
        for (int l = 0; l < 3; ++l) {
          const int l1 = (l + 1) % 3, l2 = (l + 2) % 3;
          const long double n = (long double)b[l1] * a[l2] - (long double)b[l2] * a[l1];
          exact += n * ((long double)v.d0[l] + (long double)x * v.dx[l] + (long double)y * v.dy[l]);
        }
        const double vf = double(t.orientation) * edgeR(t, i, x, y);
        const double bound = double(kEdgeBoundFactor) * ((t.errA[i] + double(x) * t.errB[i]) + double(y) * t.errC[i]);
        worstF = std::max(worstF, double(std::fabs((long double)vf - exact)) / bound);
        double boundD;
        const double vd = edgeFunctionDouble(v, a, b, x, y, boundD);
        worstD = std::max(worstD, double(std::fabs((long double)vd - exact)) / boundD);
      }
    }
  }
  std::printf("largest error / bound: float %.3f, double %.3f\n", worstF, worstD);
  EXPECT_LE(worstF, 1.0);
  EXPECT_LE(worstD, 1.0);
  EXPECT_GT(worstF, 1e-3);  // the samples do reach the rounding regime
}

// (b × a)·(a + 2b) = 0 exactly, and (b × a)·(a + δ) has the sign of (b × a)·δ however small δ is;
// plain double evaluation loses both to rounding.
TEST(Raster3dNumerics, ExactSignIsExactUnderCancellation) {
  std::mt19937 rng(6);
  std::uniform_real_distribution<float> u(-4.0f, 4.0f);
  int naiveWrong = 0;
  for (int k = 0; k < 5000; ++k) {
    const glm::vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng));
    const glm::dvec3 zero[3] = {glm::dvec3(a), glm::dvec3(b), glm::dvec3(b)};
    EXPECT_EQ(exactTripleProductSign(b, a, zero, 3), 0);
    const double tiny = std::ldexp(1.0, -70 - k % 40);
    const glm::dvec3 delta(k % 2 ? tiny : -tiny, 0.0, 0.0);
    const glm::dvec3 perturbed[2] = {glm::dvec3(a), delta};
    const double nx = double(b.y) * a.z - double(b.z) * a.y;  // exact: two 48-bit products
    if (nx == 0.0) continue;
    const int expected = (nx > 0) == (delta.x > 0) ? 1 : -1;
    EXPECT_EQ(exactTripleProductSign(b, a, perturbed, 2), expected);
    const double naive = glm::dot(glm::cross(glm::dvec3(b), glm::dvec3(a)), glm::dvec3(a) + delta);
    naiveWrong += (naive > 0 ? 1 : naive < 0 ? -1 : 0) != expected;
  }
  EXPECT_GT(naiveWrong, 100);
}

TEST(Raster3dView, PinholeRaysGoThroughPixelCentresWithForwardComponentOne) {
  Camera cam;
  cam.view = glm::lookAtRH(glm::vec3(1.3f, 0.7f, 2.1f), glm::vec3(-0.4f, 0.2f, -1.9f), glm::vec3(0.1f, 1.0f, 0.05f));
  cam.yfov = 1.0f;
  const Raster3dView v = pinholeView(cam, 64, 48);
  const glm::dmat4 view(cam.view);
  EXPECT_LT(glm::length(glm::dvec3(view * glm::dvec4(glm::dvec3(v.eye), 1.0))), 1e-6);
  const double tanHalf = std::tan(0.5), a = 64.0 / 48.0;
  for (int y = 0; y < 48; y += 7)
    for (int x = 0; x < 64; x += 9) {
      const glm::dvec3 d = glm::dvec3(view * glm::dvec4(rayAt(v, x, y), 0.0));  // view space
      const glm::dvec3 expected((2.0 * (x + 0.5) / 64 - 1) * a * tanHalf, -(2.0 * (y + 0.5) / 48 - 1) * tanHalf, -1.0);
      EXPECT_LT(glm::length(d - expected), 1e-6) << x << " " << y;
    }
}

// An eye at the origin looking down −z, 64 × 64 pixels.
Raster3dView originView() {
  Camera cam;
  cam.yfov = 1.2f;
  cam.znear = 0.1f;
  return pinholeView(cam, 64, 64);
}

TEST(Raster3dGeometry, DegenerateTrianglesCoverNothing) {
  const Raster3dView v = originView();
  const std::vector<glm::vec3> p = {{-1, -1, -3}, {1, 1, -3},  {0, 0, -3},      // collinear
                                    {-1, 0, -2},  {-1, 0, -2}, {1, 1, -4},      // a repeated vertex
                                    {-1, 0, -2},  {2, 0, -3},  {0.5f, 0, -9}};  // the eye in its plane
  const std::vector<uint32_t> idx = {0, 1, 2, 3, 4, 5, 6, 7, 8};
  Raster3dSettings s;
  s.fullScreenBoxes = true;
  const Raster3dResult r = rasterize3d(v, p, idx, s);
  EXPECT_EQ(r.counters.degenerate, 3u);
  EXPECT_EQ(r.counters.covered, 0u);
  EXPECT_GE(r.counters.orientationFallbacks, 3u);  // each needed the exact volume
}

TEST(Raster3dGeometry, TrianglesBehindTheEyeCoverNothing) {
  const Raster3dView v = originView();
  // The mirror image through the eye of a triangle that covers the whole screen.
  const std::vector<glm::vec3> p = {{-30, -30, 2},      {30, -30, 2}, {0, 40, 2},
                                    {-30, -30, 0.001f}, {30, -30, 5}, {0, 40, 1}};
  const std::vector<uint32_t> idx = {0, 1, 2, 3, 4, 5};
  Raster3dSettings s;
  s.fullScreenBoxes = true;
  EXPECT_EQ(rasterize3d(v, p, idx, s).counters.covered, 0u);
  EXPECT_EQ(rasterize3d(v, p, idx).counters.pixelsTested, 0u);  // empty boxes
}

TEST(Raster3dGeometry, OrientationIsPlusOneForCounterClockwiseSeenFromTheEyeAndBothFacesAreDrawn) {
  const Raster3dView v = originView();
  const std::vector<glm::vec3> p = {{0, 0, -1}, {1, 0, -1}, {0, 1, -1}};
  Raster3dTriangle t;
  Raster3dRefCounters c;
  ASSERT_TRUE(setupTriangle3d(v, p[0], p[1], p[2], t, c));
  EXPECT_EQ(t.orientation, 1);
  ASSERT_TRUE(setupTriangle3d(v, p[0], p[2], p[1], t, c));
  EXPECT_EQ(t.orientation, -1);
  const std::vector<uint32_t> ccw = {0, 1, 2}, cw = {0, 2, 1};
  const Raster3dResult a = rasterize3d(v, p, ccw), b = rasterize3d(v, p, cw);
  EXPECT_GT(a.counters.covered, 100u);
  EXPECT_EQ(a.coverage, b.coverage);
  EXPECT_EQ(a.visibility, b.visibility);
}

// Per pixel: the triangle and its view depth from the ray cast's side (double, unrounded vertices).
struct DoubleHit {
  double minEdge = 0;          // min_i |V_i| / (its edge-tie bound): <= 1 means within rounding of an edge
  double t = 0, relBound = 0;  // t and the derived bound on the rasterizer's relative error in t
};

// Derived tolerances. Edge: the rasterizer decides exactly for the eye-relative vertices rounded to
// float, each coordinate moved by <= u·|p_l|; that moves V_i = (b × a)·d by <= 2u·Σ_l G'_l·|d_l|
// (G'_l the terms of (b × a)_l) to first order: 2.1u bounds it with the double's own rounding.
// Depth: t = det/(N·d); to first order its relative error is at most
//   u·max_k Σ_l |N_l||p_kl| / |det|     (vertex rounding: the plane moves by N̂·δp at the hit)
//   + γ_7·Σ_l GN_l·|p0_l| / |det|       (det in float, raster3d_ref.cpp)
//   + γ_9·Σ_l GN_l·H_l / |N·d|          (N·d in float, d = d0 + x·dx + y·dy rounded twice)
//   + u                                  (the division), all times 1.01 for the second order.
DoubleHit doubleHit(const Raster3dView& v, const std::vector<glm::vec3>& pos, const std::vector<uint32_t>& idx,
                    uint32_t id, uint32_t x, uint32_t y) {
  glm::dvec3 p[3];
  for (int i = 0; i < 3; ++i) p[i] = glm::dvec3(pos[idx[3 * id + i]]) - glm::dvec3(v.eye);
  const glm::dvec3 d = rayAt(v, x, y), e1 = p[1] - p[0], e2 = p[2] - p[0], n = glm::cross(e1, e2);
  const glm::dvec3 h =
      glm::abs(glm::dvec3(v.d0)) + double(x) * glm::abs(glm::dvec3(v.dx)) + double(y) * glm::abs(glm::dvec3(v.dy));
  const glm::dvec3 gn(std::fabs(e1.y * e2.z) + std::fabs(e1.z * e2.y), std::fabs(e1.z * e2.x) + std::fabs(e1.x * e2.z),
                      std::fabs(e1.x * e2.y) + std::fabs(e1.y * e2.x));
  DoubleHit r;
  const double det = glm::dot(n, p[0]), den = glm::dot(n, d);
  r.t = det / den;
  double vertexTerm = 0;
  for (int k = 0; k < 3; ++k) vertexTerm = std::max(vertexTerm, glm::dot(glm::abs(n), glm::abs(p[k])));
  r.relBound = 1.01 * (kU * vertexTerm / std::fabs(det) + gamma(7) * glm::dot(gn, glm::abs(p[0])) / std::fabs(det) +
                       gamma(9) * glm::dot(gn, h) / std::fabs(den) + kU);
  r.minEdge = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) {
    const glm::dvec3 a = p[(i + 1) % 3], b = p[(i + 2) % 3];
    const glm::dvec3 g(std::fabs(b.y * a.z) + std::fabs(b.z * a.y), std::fabs(b.z * a.x) + std::fabs(b.x * a.z),
                       std::fabs(b.x * a.y) + std::fabs(b.y * a.x));
    r.minEdge = std::min(r.minEdge, std::fabs(glm::dot(glm::cross(b, a), d)) / (2.1 * kU * glm::dot(g, glm::abs(d))));
  }
  return r;
}

struct Agreement {
  size_t hits = 0, sameId = 0, edgeTies = 0, depthTies = 0, unexplained = 0, depthOutOfBound = 0;
  std::vector<double> relDepthError;
};

Agreement compareWithRayCast(const Raster3dView& v, const std::vector<glm::vec3>& pos, const std::vector<uint32_t>& idx,
                             const Raster3dResult& r) {
  const RayCastResult ref = rayCast3d(v, pos, idx);
  Agreement a;
  for (uint32_t y = 0; y < v.height; ++y)
    for (uint32_t x = 0; x < v.width; ++x) {
      const size_t i = size_t(y) * v.width + x;
      const uint32_t s = r.visibility[i] == kNoHit ? kNoTriangle : visibilityId(r.visibility[i]);
      const RayCastHit& h = ref.nearest[i];
      if (s == kNoTriangle && h.id == kNoTriangle) continue;
      ++a.hits;
      if (s == h.id) {
        ++a.sameId;
        const double err = std::fabs(double(visibilityDepth(r.visibility[i])) - h.t) / h.t;
        a.relDepthError.push_back(err);
        a.depthOutOfBound += err > doubleHit(v, pos, idx, s, x, y).relBound;
        continue;
      }
      const DoubleHit hs = s == kNoTriangle ? DoubleHit{} : doubleHit(v, pos, idx, s, x, y);
      const DoubleHit hr = h.id == kNoTriangle ? DoubleHit{} : doubleHit(v, pos, idx, h.id, x, y);
      if ((s != kNoTriangle && hs.minEdge <= 1.0) || (h.id != kNoTriangle && hr.minEdge <= 1.0))
        ++a.edgeTies;
      else if (s != kNoTriangle && h.id != kNoTriangle &&
               std::fabs(hs.t - hr.t) <= hs.relBound * hs.t + hr.relBound * hr.t)
        ++a.depthTies;
      else
        ++a.unexplained;
    }
  return a;
}

double percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[std::min(v.size() - 1, size_t(q * double(v.size())))];
}

TEST(Raster3dGeometry, TrianglesCrossingTheEyePlaneDrawOnlyTheirVisiblePartAsTheRayCast) {
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> u(-3.0f, 3.0f);
  const Raster3dView v = originView();
  std::vector<glm::vec3> p;
  std::vector<uint32_t> idx;
  for (uint32_t k = 0; k < 30; ++k) {  // one or two vertices behind the eye, the rest in front
    p.push_back({u(rng), u(rng), 1.0f + u(rng) * 0.3f});
    p.push_back({u(rng), u(rng), -2.0f + u(rng)});
    p.push_back({u(rng), u(rng), k % 2 ? -4.0f + u(rng) * 0.5f : 0.5f});
    idx.insert(idx.end(), {3 * k, 3 * k + 1, 3 * k + 2});
  }
  for (bool full : {false, true}) {
    Raster3dSettings s;
    s.fullScreenBoxes = full;
    const Raster3dResult r = rasterize3d(v, p, idx, s);
    const Agreement a = compareWithRayCast(v, p, idx, r);
    EXPECT_GT(a.sameId, 3000u);
    EXPECT_EQ(a.unexplained, 0u);
    EXPECT_LE(a.edgeTies + a.depthTies, a.hits / 1000);
  }
}

// A random scene: a heightfield (shared edges and vertices) and a soup of random triangles through
// it (intersections: depth ties), under 4 random views.
TEST(Raster3dAccuracy, IdsAndDepthsMatchTheDoubleRayCastOnARandomMesh) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Agreement total;
  Raster3dRefCounters c;
  for (int view = 0; view < 4; ++view) {
    const Raster3dView v = randomView(rng, 320, 240);
    std::vector<glm::vec3> pos;
    std::vector<uint32_t> idx;
    constexpr int kN = 60;
    for (int j = 0; j <= kN; ++j)
      for (int i = 0; i <= kN; ++i)
        pos.push_back(
            glm::vec3(glm::dvec3(v.eye) + (5.0 + 0.3 * u(rng)) * rayAt(v, -20 + (i + 0.8 * u(rng)) * 360.0 / kN,
                                                                       -20 + (j + 0.8 * u(rng)) * 280.0 / kN)));
    for (int j = 0; j < kN; ++j)
      for (int i = 0; i < kN; ++i) {
        const uint32_t a = j * (kN + 1) + i, b = a + 1, d = a + kN + 1, e = d + 1;
        idx.insert(idx.end(), {a, b, e, a, e, d});
      }
    for (int k = 0; k < 1500; ++k) {
      const glm::dvec3 centre = glm::dvec3(v.eye) + (2.0 + 6.0 * u(rng)) * rayAt(v, 320 * u(rng), 240 * u(rng));
      for (int i = 0; i < 3; ++i) {
        idx.push_back(uint32_t(pos.size()));
        pos.push_back(glm::vec3(centre + 0.4 * glm::dvec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5)));
      }
    }
    const Raster3dResult r = rasterize3d(v, pos, idx);
    const Agreement a = compareWithRayCast(v, pos, idx, r);
    total.hits += a.hits, total.sameId += a.sameId, total.edgeTies += a.edgeTies, total.depthTies += a.depthTies;
    total.unexplained += a.unexplained, total.depthOutOfBound += a.depthOutOfBound;
    total.relDepthError.insert(total.relDepthError.end(), a.relDepthError.begin(), a.relDepthError.end());
    c.edgeEvaluations += r.counters.edgeEvaluations, c.fallbacks += r.counters.fallbacks;
    c.exactEvaluations += r.counters.exactEvaluations;
  }
  const double p999 = percentile(total.relDepthError, 0.999), worst = percentile(total.relDepthError, 1.0);
  std::printf(
      "random mesh: %zu hits, %zu same id (%.5f %%), %zu edge ties, %zu depth ties, %zu unexplained; "
      "relative depth error p99.9 %.3g, max %.3g, %zu beyond the derived bound; fallback %.3f %% of %llu, exact %llu\n",
      total.hits, total.sameId, 100.0 * total.sameId / total.hits, total.edgeTies, total.depthTies, total.unexplained,
      p999, worst, total.depthOutOfBound, 100.0 * c.fallbacks / c.edgeEvaluations,
      (unsigned long long)c.edgeEvaluations, (unsigned long long)c.exactEvaluations);
  EXPECT_GT(total.hits, 250000u);
  EXPECT_GE(double(total.sameId), 0.99999 * double(total.hits));
  EXPECT_EQ(total.unexplained, 0u);
  EXPECT_EQ(total.depthOutOfBound, 0u);
  EXPECT_LE(p999, 1e-6);
}

}  // namespace
}  // namespace hb
