// 3D rasterization reference: the fill rule (mirroring VK-GL-CTS's fill-rule tests: coverage is
// counted additively over all triangles, whatever their depth), the numerics of the edge
// functions, and agreement with the double-precision ray cast. Fixed seeds throughout.
#include "reference/raster3d_ref.h"
#include "reference/raster3d_ref_test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <map>
#include <random>
#include <vector>

namespace hb {
namespace {

using raster3d_test::liftOntoPlane;
using raster3d_test::Mesh;
using raster3d_test::PixelMesh;
using raster3d_test::quadGrid;
using raster3d_test::randomView;
using raster3d_test::rayAt;

double area2(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }

// True if every triangle is non-degenerate with one winding on screen (a valid planar partition).
bool isPartition(const PixelMesh& m) {
  int sign = 0;
  for (size_t k = 0; k < m.indices.size(); k += 3) {
    const double a = area2(m.px[m.indices[k]], m.px[m.indices[k + 1]], m.px[m.indices[k + 2]]);
    if (std::fabs(a) < 0.5 || (sign != 0 && (a > 0) != (sign > 0))) return false;
    sign = a > 0 ? 1 : -1;
  }
  return true;
}

// k triangles around a vertex on a pixel centre; outer vertices on pixel centres too.
PixelMesh fan(int k, glm::dvec2 centre, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  PixelMesh f;
  f.px.push_back(centre);
  std::vector<double> angles;
  for (int i = 0; i < k; ++i) angles.push_back((i + 0.15 + 0.7 * u(rng)) * 2.0 * M_PI / k);
  for (double a : angles) {
    const double r = 4.0 + 10.0 * u(rng);
    f.px.push_back(glm::round(centre + r * glm::dvec2(std::cos(a), std::sin(a))));
  }
  for (int i = 0; i < k; ++i) {
    f.indices.insert(f.indices.end(), {0u, uint32_t(1 + i), uint32_t(1 + (i + 1) % k)});
    f.outline.push_back(uint32_t(1 + i));
  }
  return f;
}

struct FillStats {
  size_t inside = 0, holes = 0, doubleCovers = 0, spill = 0;
};

// Classifies every pixel by the outline in pixel coordinates: inside (crossing parity) or outside,
// except pixels within 0.01 px of the outline, which may go either way (the outline is not shared).
// The vertices' rounding to float moves them by ~1e-4 px, far less than the margin.
FillStats checkFill(const PixelMesh& pm, const std::vector<uint32_t>& coverage, uint32_t w, uint32_t h) {
  constexpr double kMargin = 0.01;
  std::vector<uint8_t> nearOutline(size_t(w) * h, 0);
  std::vector<std::vector<double>> crossings(h);
  for (size_t k = 0; k < pm.outline.size(); ++k) {
    const glm::dvec2 a = pm.px[pm.outline[k]], b = pm.px[pm.outline[(k + 1) % pm.outline.size()]];
    for (int y = std::max(0, int(std::floor(std::min(a.y, b.y))) - 1);
         y <= std::min(int(h) - 1, int(std::ceil(std::max(a.y, b.y))) + 1); ++y) {
      if ((a.y <= y) != (b.y <= y)) crossings[y].push_back(a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y));
      for (int x = std::max(0, int(std::floor(std::min(a.x, b.x))) - 1);
           x <= std::min(int(w) - 1, int(std::ceil(std::max(a.x, b.x))) + 1); ++x) {
        const glm::dvec2 p(x, y), ab = b - a;
        const double s = std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0, 1.0);
        if (glm::length(p - (a + s * ab)) < kMargin) nearOutline[size_t(y) * w + x] = 1;
      }
    }
  }
  FillStats r;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const uint32_t c = coverage[i];
      r.doubleCovers += c >= 2;
      if (nearOutline[i]) continue;
      const bool inside =
          std::count_if(crossings[y].begin(), crossings[y].end(), [&](double cx) { return cx < x; }) % 2 == 1;
      r.inside += inside;
      r.holes += inside && c == 0;
      r.spill += !inside && c != 0;
    }
  return r;
}

struct Totals {
  FillStats fill;
  Raster3dRefCounters counters;
  void add(const FillStats& f, const Raster3dRefCounters& c) {
    fill.inside += f.inside, fill.holes += f.holes, fill.doubleCovers += f.doubleCovers, fill.spill += f.spill;
    counters.edgeEvaluations += c.edgeEvaluations, counters.fallbacks += c.fallbacks;
    counters.exactEvaluations += c.exactEvaluations;
  }
  void print(const char* what) const {
    std::printf(
        "%s: %zu inside, %zu holes, %zu double covers, %zu spill; fallback %llu of %llu edge evaluations "
        "(%.3f %%), exact %llu\n",
        what, fill.inside, fill.holes, fill.doubleCovers, fill.spill, (unsigned long long)counters.fallbacks,
        (unsigned long long)counters.edgeEvaluations, 100.0 * counters.fallbacks / counters.edgeEvaluations,
        (unsigned long long)counters.exactEvaluations);
  }
};

// The worst case: 100 × 100 quads with a vertex on every pixel centre (step 1 px), under 16
// random perspectives (random camera, plane tilted up to 60°).
Totals denseGrids(bool fallback) {
  std::mt19937 rng(1234);
  Totals tot;
  for (int k = 0; k < 16; ++k) {
    const Raster3dView v = randomView(rng, 128, 128);
    const PixelMesh g = quadGrid(100, 1.0, (k % 4) * M_PI / 2, {63.5, 63.5}, true);
    const Mesh m = liftOntoPlane(v, g, 3.0, (k % 5) * 0.3, rng);
    Raster3dSettings s;
    s.fp64Fallback = fallback;
    const Raster3dResult r = rasterize3d(v, m.positions, m.indices, s);
    tot.add(checkFill(g, r.coverage, v.width, v.height), r.counters);
  }
  return tot;
}

TEST(Raster3dFillRule, DenseGridWithAVertexOnEveryPixelCentreIsCoveredExactlyOnce) {
  const Totals t = denseGrids(true);
  t.print("dense grid, fallback");
  EXPECT_GT(t.fill.inside, 16u * 9000u);
  EXPECT_EQ(t.fill.holes, 0u);
  EXPECT_EQ(t.fill.doubleCovers, 0u);
  EXPECT_EQ(t.fill.spill, 0u);
  EXPECT_GT(t.counters.fallbacks, 0u);
}

TEST(Raster3dFillRule, WithoutTheFallbackTheDenseGridHasHolesOrDoubleCovers) {
  const Totals t = denseGrids(false);
  t.print("dense grid, no fallback");
  EXPECT_GT(t.fill.holes + t.fill.doubleCovers, 0u);  // what the fallback is for
}

TEST(Raster3dFillRule, RotatedGridsWithVerticesOnPixelCentresAreCoveredExactlyOnceAt16Angles) {
  std::mt19937 rng(77);
  Totals tot;
  for (int k = 0; k < 16; ++k) {
    const double angle = k * (M_PI / 16.0) + 0.013 * (k % 3);
    SCOPED_TRACE("angle " + std::to_string(angle));
    const Raster3dView v = randomView(rng, 440, 440);
    const PixelMesh g = quadGrid(100, 3.0, angle, {219.5, 219.5}, true);
    ASSERT_TRUE(isPartition(g));
    const Mesh m = liftOntoPlane(v, g, 4.0, 0.2 + (k % 4) * 0.3, rng);
    const Raster3dResult r = rasterize3d(v, m.positions, m.indices);
    const FillStats f = checkFill(g, r.coverage, v.width, v.height);
    EXPECT_GT(f.inside, 80000u);
    EXPECT_EQ(f.holes, 0u);
    EXPECT_EQ(f.doubleCovers, 0u);
    EXPECT_EQ(f.spill, 0u);
    tot.add(f, r.counters);
  }
  tot.print("rotated grids, fallback");
}

TEST(Raster3dFillRule, FansAroundAVertexOnAPixelCentreAreCoveredExactlyOnce) {
  std::mt19937 rng(9);
  Totals tot;
  for (int k = 0; k < 60; ++k) {
    const Raster3dView v = randomView(rng, 48, 48);
    const PixelMesh f = fan(3 + k % 10, {23.0 + k % 3, 24.0}, rng);
    if (!isPartition(f)) continue;  // a snapped outer vertex folded a thin triangle: not a fan
    const Mesh m = liftOntoPlane(v, f, 2.0, (k % 5) * 0.25, rng);
    const Raster3dResult r = rasterize3d(v, m.positions, m.indices);
    const FillStats s = checkFill(f, r.coverage, v.width, v.height);
    EXPECT_EQ(s.holes + s.doubleCovers + s.spill, 0u) << "fan " << k;
    EXPECT_EQ(r.coverage[24 * 48 + 23 + k % 3], 1u) << "the centre vertex's pixel, fan " << k;
    tot.add(s, r.counters);
  }
  EXPECT_GT(tot.fill.inside, 5000u);
  tot.print("fans, fallback");
}

// An axis-aligned view with dyadic constants: the edge functions are exact, many are exactly zero
// at pixel centres, and the top-left rule of Section 3.4 decides. Pixel (x, y) <-> (x/8 − 0.5,
// 0.5 − y/8, −1) at depth 1.
Raster3dView dyadicView() {
  Raster3dView v;
  v.eye = glm::vec3(0.0f);
  v.d0 = glm::vec3(-0.5f, 0.5f, -1.0f);
  v.dx = glm::vec3(0.125f, 0.0f, 0.0f);
  v.dy = glm::vec3(0.0f, -0.125f, 0.0f);
  v.width = v.height = 8;
  return v;
}

uint32_t idAt(const Raster3dResult& r, int x, int y) { return visibilityId(r.visibility[y * r.width + x]); }

TEST(Raster3dTieRule, CentresOnSharedEdgesAndVerticesGoToTheTriangleRightOrBelow) {
  const Raster3dView v = dyadicView();
  auto at = [&](int x, int y) { return glm::vec3(rayAt(v, x, y)); };
  {  // a vertical shared edge x = 3: its centres go to the triangle on the right (id 1)
    const Mesh m{{at(3, 0), at(3, 7), at(0, 3), at(7, 4)}, {0, 1, 2, 1, 0, 3}};
    const Raster3dResult r = rasterize3d(v, m.positions, m.indices);
    for (int y = 1; y <= 6; ++y) EXPECT_EQ(idAt(r, 3, y), 1u) << y;
    EXPECT_GT(r.counters.exactEvaluations, 0u);
  }
  {  // a horizontal shared edge y = 3: its centres go to the triangle below (id 0)
    const Mesh m{{at(0, 3), at(7, 3), at(4, 7), at(3, 0)}, {0, 1, 2, 1, 0, 3}};
    const Raster3dResult r = rasterize3d(v, m.positions, m.indices);
    for (int x = 1; x <= 6; ++x) EXPECT_EQ(idAt(r, x, 3), 0u) << x;
  }
  {  // a fan of 6 around pixel (4, 4), wound both ways: the centre goes to the triangle that holds
     // the point moved by (ε, ε²), i.e. the one right of the vertex and just below the horizontal
    const std::vector<glm::ivec2> ring = {{7, 4}, {6, 7}, {2, 7}, {0, 4}, {2, 0}, {6, 0}};
    for (bool reversed : {false, true}) {
      Mesh m{{at(4, 4)}, {}};
      for (glm::ivec2 p : ring) m.positions.push_back(at(p.x, p.y));
      for (uint32_t i = 0; i < 6; ++i) {
        const uint32_t a = 1 + i, b = 1 + (i + 1) % 6;
        m.indices.insert(m.indices.end(), {0u, reversed ? b : a, reversed ? a : b});
      }
      const Raster3dResult r = rasterize3d(v, m.positions, m.indices);
      EXPECT_EQ(r.coverage[4 * 8 + 4], 1u);
      EXPECT_EQ(idAt(r, 4, 4), 0u);  // triangle (centre, (7,4), (6,7)): below the ray to the right
      for (uint32_t c : r.coverage) EXPECT_LE(c, 1u);
    }
  }
}

// A closed mesh: an icosphere (consistently wound, every edge shared by two triangles).
Mesh icosphere(int levels) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<glm::dvec3> p = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                               {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  std::vector<uint32_t> idx = {0, 11, 5,  0, 5,  1, 0, 1, 7, 0, 7,  10, 0, 10, 11, 1, 5, 9, 5, 11,
                               4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3,  9,  4, 3,  4,  2, 3, 2, 6, 3,
                               6, 8,  3,  8, 9,  4, 9, 5, 2, 4, 11, 6,  2, 10, 8,  6, 7, 9, 8, 1};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      const auto key = std::minmax(a, b);
      auto [it, added] = mid.try_emplace(key, uint32_t(p.size()));
      if (added) p.push_back((p[a] + p[b]) * 0.5);
      return it->second;
    };
    std::vector<uint32_t> next;
    for (size_t k = 0; k < idx.size(); k += 3) {
      const uint32_t a = idx[k], b = idx[k + 1], c = idx[k + 2];
      const uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
    }
    idx = next;
  }
  Mesh m;
  for (const glm::dvec3& q : p) m.positions.push_back(glm::vec3(glm::normalize(q)));
  m.indices = idx;
  return m;
}

// Moves the sphere to `centre` (world) with `radius`, jitters it, and optionally moves every vertex
// onto the ray through its nearest pixel centre at the same depth (the worst case for vertices).
Mesh placeSphere(Mesh m, const Raster3dView& v, glm::dvec3 centre, double radius, bool snap, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const glm::dmat3 toPixel = glm::inverse(glm::dmat3(glm::dvec3(v.dx), glm::dvec3(v.dy), glm::dvec3(v.d0)));
  for (glm::vec3& p : m.positions) {
    glm::dvec3 q = centre + radius * (glm::dvec3(p) + 0.02 * glm::dvec3(u(rng), u(rng), u(rng))) - glm::dvec3(v.eye);
    if (snap) {
      const glm::dvec3 s = toPixel * q;  // (x·t, y·t, t)
      q = s.z * rayAt(v, std::round(s.x / s.z), std::round(s.y / s.z));
    }
    p = glm::vec3(glm::dvec3(v.eye) + q);
  }
  return m;
}

// Coverage of the triangles of one orientation (as the rasterizer's setup decides it).
std::vector<uint32_t> coverageOfFaces(const Raster3dView& v, const Mesh& m, int orientation, Raster3dRefCounters& c) {
  Mesh part{m.positions, {}};
  for (size_t k = 0; k < m.indices.size(); k += 3) {
    Raster3dTriangle tri;
    Raster3dRefCounters unused;
    if (setupTriangle3d(v, m.positions[m.indices[k]], m.positions[m.indices[k + 1]], m.positions[m.indices[k + 2]], tri,
                        unused) &&
        tri.orientation == orientation)
      part.indices.insert(part.indices.end(), m.indices.begin() + k, m.indices.begin() + k + 3);
  }
  const Raster3dResult r = rasterize3d(v, part.positions, part.indices);
  c.edgeEvaluations += r.counters.edgeEvaluations, c.fallbacks += r.counters.fallbacks;
  return r.coverage;
}

// A ray from an eye outside a closed mesh crosses it as often front to back as back to front
// (winding number 0 at the eye), so per pixel the front and back coverage are equal: a hole or a
// double cover in either layer breaks it, wherever it falls.
TEST(Raster3dFillRule, ClosedMeshesSeenFromOutsideCoverEveryPixelAsOftenFrontAsBack) {
  std::mt19937 rng(31);
  size_t covered = 0, mismatches = 0;
  Raster3dRefCounters c;
  for (int k = 0; k < 6; ++k) {
    const Raster3dView v = randomView(rng, 160, 120);
    const glm::dvec3 centre = glm::dvec3(v.eye) + 4.0 * rayAt(v, 70 + 5 * k, 60);
    const Mesh m = placeSphere(icosphere(4), v, centre, 1.2, k % 2 == 1, rng);
    const std::vector<uint32_t> front = coverageOfFaces(v, m, 1, c), back = coverageOfFaces(v, m, -1, c);
    for (size_t i = 0; i < front.size(); ++i) {
      covered += front[i] != 0;
      mismatches += front[i] != back[i];
    }
  }
  std::printf("closed meshes: %zu pixels covered, %zu front/back mismatches; fallback %.3f %% of %llu\n", covered,
              mismatches, 100.0 * c.fallbacks / c.edgeEvaluations, (unsigned long long)c.edgeEvaluations);
  EXPECT_GT(covered, 20000u);
  EXPECT_EQ(mismatches, 0u);
}

// From inside a closed sphere every ray leaves it exactly once; the sphere has triangles behind the
// eye and triangles crossing the eye plane, which are rasterized without clipping.
TEST(Raster3dFillRule, EyeInsideAClosedMeshCoversEveryPixelExactlyOnce) {
  std::mt19937 rng(5);
  for (int k = 0; k < 4; ++k) {
    Raster3dView v = randomView(rng, 96, 80);
    v.znear = 0.01f;
    const Mesh m = placeSphere(icosphere(3), v, glm::dvec3(v.eye) + glm::dvec3(0.1, -0.05, 0.07), 2.0, false, rng);
    for (bool full : {false, true}) {
      Raster3dSettings s;
      s.fullScreenBoxes = full;
      const Raster3dResult r = rasterize3d(v, m.positions, m.indices, s);
      EXPECT_EQ(size_t(std::count(r.coverage.begin(), r.coverage.end(), 1u)), r.coverage.size()) << k << full;
    }
  }
}

}  // namespace
}  // namespace hb
