// 3D rasterization (primary=3dr) on the real device: the fill rule, mirroring VK-GL-CTS's fill-rule
// tests (every pixel inside a mesh is covered exactly once, counted additively over all triangles
// whatever their depth), degenerate triangles, triangles crossing the eye plane, and the frame on
// top of it. Scenes are built so that the answer is known exactly in double precision.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "analysis/primary_analysis.h"
#include "base/errors.h"
#include "base/image_io.h"
#include "effects/shadows/shadows_part.h"
#include "frame/passes/raster3d.h"
#include "frame/renderer.h"
#include "gpu_fixture.h"
#include "reference/flip.h"
#include "scene/atrium.h"
#include "scene/hard_cases.h"
#include "scene/mesh_builder.h"

namespace hb {
namespace {

constexpr uint32_t kSize = 64;

Camera originCamera() {
  Camera cam;
  cam.view = glm::mat4(1.0f);  // eye at the origin looking down -z
  cam.yfov = 1.0f;
  cam.znear = 0.1f;
  cam.zfar = 100.0f;
  return cam;
}

// A camera away from the origin and off every axis, so that no product in the edge functions is
// exact by accident (an axis-aligned camera at the origin makes most of them exact zeros).
Camera obliqueCamera() {
  Camera cam = originCamera();
  cam.view = lookAt(glm::vec3(1.37f, 0.71f, 2.13f), glm::vec3(-0.4f, 0.2f, -1.9f), glm::vec3(0.1f, 1.0f, 0.05f));
  return cam;
}

// The pixel-centre ray of the 3DR pass, in double from the same float constants.
struct Rays {
  gpu::Raster3dConstants c;
  explicit Rays(const Camera& cam) : c(raster3dConstants(cam, kSize, kSize, 0, 0)) {}
  glm::dvec3 at(double x, double y) const {  // eye-relative
    return glm::dvec3(c.rayD0) + x * glm::dvec3(c.rayDx) + y * glm::dvec3(c.rayDy);
  }
  glm::dvec3 eye() const { return glm::dvec3(c.eye); }
};

Scene emptyScene(const char* name, const Camera& cam = originCamera()) {
  Scene s;
  s.name = name;
  s.materials.push_back({});
  s.cameras.push_back(cam);
  return s;
}

void addTriangles(Scene& s, const std::vector<glm::dvec3>& corners) {  // 3 per triangle
  const uint32_t first = uint32_t(s.indices.size()), base = uint32_t(s.vertices.size());
  for (size_t i = 0; i < corners.size(); ++i) {
    s.vertices.push_back({glm::vec3(corners[i]), glm::vec3(0, 0, 1), glm::vec2(0)});
    s.indices.push_back(uint32_t(i));
  }
  s.meshes.push_back({"mesh", {{first, uint32_t(corners.size()), base, uint32_t(corners.size()), 0}}});
  s.instances.push_back({uint32_t(s.meshes.size() - 1), glm::mat4(1.0f)});
}

struct Coverage {
  std::vector<uint32_t> count;
  std::vector<uint64_t> vis;
  Raster3dCounters counters;
};

Coverage rasterize(const VulkanContext& ctx, const Scene& scene, bool fp64Fallback = true, const char* primary = "3dr",
                   uint32_t width = kSize, uint32_t height = kSize) {
  RenderSettings rs;
  rs.width = width;
  rs.height = height;
  rs.primary = hb::testing::primaryNamed(primary);
  rs.fp64Fallback = fp64Fallback;
  rs.effects.add(EffectSource::Config, "test", {{"shadows", false}});
  Renderer r(ctx, scene, rs);
  r.renderFrame(true);
  return {r.raster3d()->readCoverage(), r.raster3d()->readVisibility(), r.raster3d()->readCounters()};
}

// A grid of n x n quads whose vertices lie on the rays through pixel centres (cx + i·step,
// cy + j·step) at view depth 2, then moved rigidly by `pose` about the grid's centre. Returns the
// corner P00 (eye-relative) and the edges to P(n,0), P(0,n) of the parallelogram it spans (for the
// exact inside test).
struct Grid {
  glm::dvec3 origin, u, v;
};
// Pixel coordinates are those of the centres (Rays::at), so with shift 0 and n·step even the
// vertices fall on pixel corners and the cells' diagonals through the centres; shift 0.5 puts them
// on centres.
Grid addGrid(Scene& s, const Rays& rays, int n, double step, const glm::dmat4& pose, double shift = 0.0) {
  const double c0 = kSize / 2.0 - 0.5 - n * step / 2.0 + shift;  // pixel coordinate of vertex (0, 0)
  const glm::dvec3 centre = 2.0 * rays.at(kSize / 2.0 - 0.5, kSize / 2.0 - 0.5);
  // A pose in view space: the camera's rotation carries it to world space.
  const glm::dmat3 toWorld = glm::dmat3(glm::inverse(glm::dmat4(s.cameras[0].view)));
  auto vertex = [&](int i, int j) {
    const glm::dvec3 p = 2.0 * rays.at(c0 + i * step, c0 + j * step);
    const glm::dvec3 inView = glm::transpose(toWorld) * (p - centre);
    return rays.eye() + centre + toWorld * glm::dvec3(pose * glm::dvec4(inView, 1.0));
  };
  std::vector<glm::dvec3> tris;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const glm::dvec3 a = vertex(i, j), b = vertex(i + 1, j), c = vertex(i + 1, j + 1), d = vertex(i, j + 1);
      // Alternate the diagonal so that vertices of both valences 4 and 8 occur (as in the CTS).
      if ((i + j) % 2 == 0)
        tris.insert(tris.end(), {a, b, c, a, c, d});
      else
        tris.insert(tris.end(), {a, b, d, b, c, d});
    }
  // Shared vertices must be bitwise shared: round through float once, as the scene stores them.
  addTriangles(s, tris);
  const glm::dvec3 o = glm::dvec3(glm::vec3(vertex(0, 0)));
  return {o - rays.eye(), glm::dvec3(glm::vec3(vertex(n, 0))) - o, glm::dvec3(glm::vec3(vertex(0, n))) - o};
}

// Where the pixel's ray meets the grid's plane, in the grid's (a, b) coordinates ([0,1]² inside).
glm::dvec2 gridCoordinates(const Grid& g, const glm::dvec3& dir) {
  const glm::dvec3 n = glm::cross(g.u, g.v);
  const double t = glm::dot(n, g.origin) / glm::dot(n, dir);
  const glm::dvec3 h = t * dir - g.origin;
  // Solve h = a·u + b·v (h lies in the plane) by the 2x2 normal equations.
  const double uu = glm::dot(g.u, g.u), uv = glm::dot(g.u, g.v), vv = glm::dot(g.v, g.v);
  const double hu = glm::dot(h, g.u), hv = glm::dot(h, g.v), det = uu * vv - uv * uv;
  return {(hu * vv - hv * uv) / det, (hv * uu - hu * uv) / det};
}

struct FillResult {
  size_t inside = 0, holes = 0, doubleCovers = 0, spill = 0;
};

// Margin in grid coordinates: a centre within 1e-3 of the grid's outline (0.05 px here) may go
// either way (the outline is not shared with another triangle), so it is not counted.
FillResult checkGrid(const Coverage& cov, const Grid& g, const Rays& rays) {
  constexpr double kMargin = 1e-3;
  FillResult r;
  for (uint32_t y = 0; y < kSize; ++y)
    for (uint32_t x = 0; x < kSize; ++x) {
      const uint32_t c = cov.count[y * kSize + x];
      const glm::dvec2 ab = gridCoordinates(g, rays.at(x, y));
      const bool inside = ab.x > kMargin && ab.x < 1 - kMargin && ab.y > kMargin && ab.y < 1 - kMargin;
      const bool outside = ab.x < -kMargin || ab.x > 1 + kMargin || ab.y < -kMargin || ab.y > 1 + kMargin;
      r.inside += inside;
      r.holes += inside && c == 0;
      r.doubleCovers += c >= 2;
      r.spill += outside && c != 0;
    }
  return r;
}

// Every pixel inside covered once, none twice, none outside.
void expectExactlyOnce(const FillResult& r, size_t minInside) {
  EXPECT_GT(r.inside, minInside);
  EXPECT_EQ(r.holes, 0u);
  EXPECT_EQ(r.doubleCovers, 0u);
  EXPECT_EQ(r.spill, 0u);
}

// The atrium tests' frame: 160x90 on top of 3dr.
RenderSettings atrium3drSettings() {
  RenderSettings rs;
  rs.width = 160;
  rs.height = 90;
  rs.primary = hb::testing::primaryNamed("3dr");
  return rs;
}

class Raster3dTest : public testing::GpuTest {};

TEST_F(Raster3dTest, QuadGridWithVerticesOnPixelCentresIsCoveredExactlyOnceAt16Angles) {
  const Rays rays(obliqueCamera());
  uint64_t fallbacks = 0, evaluations = 0;
  for (int k = 0; k < 16; ++k) {
    const double angle = k * (M_PI / 16.0) + (k % 2) * 0.01;  // 0, 11.25°, ... and off-grid angles
    SCOPED_TRACE("angle " + std::to_string(angle * 180 / M_PI) + " deg");
    Scene s = emptyScene("grid", obliqueCamera());
    const Grid g = addGrid(s, rays, 16, 3.0, glm::rotate(glm::dmat4(1.0), angle, glm::dvec3(0, 0, 1)));
    const Coverage cov = rasterize(*ctx, s);
    const FillResult r = checkGrid(cov, g, rays);
    expectExactlyOnce(r, 1500);
    fallbacks += cov.counters.fallbacks;
    evaluations += cov.counters.edgeEvaluations;
  }
  // Vertices on pixel centres are the fallback's worst case: it must have run.
  EXPECT_GT(fallbacks, 0u);
  std::printf("fill rule, 16 angles: fp64 fallback on %llu of %llu edge evaluations (%.2f %%)\n",
              (unsigned long long)fallbacks, (unsigned long long)evaluations, 100.0 * fallbacks / evaluations);
}

// The worst case of the CPU trial: a vertex on every pixel centre (60 x 60 quads, step
// 1 px, no rotation), and the same at a small rotation and at a quarter-pixel offset.
std::vector<glm::dmat4> denseGridPoses() {
  return {glm::dmat4(1.0), glm::rotate(glm::dmat4(1.0), 0.003, glm::dvec3(0, 0, 1)),
          glm::rotate(glm::dmat4(1.0), M_PI / 2, glm::dvec3(0, 0, 1))};
}

TEST_F(Raster3dTest, DenseGridWithAVertexOnEveryPixelCentreIsCoveredExactlyOnce) {
  const Rays rays(obliqueCamera());
  for (const glm::dmat4& pose : denseGridPoses()) {
    Scene s = emptyScene("grid", obliqueCamera());
    const Grid g = addGrid(s, rays, 60, 1.0, pose);
    const Coverage cov = rasterize(*ctx, s);
    const FillResult r = checkGrid(cov, g, rays);
    expectExactlyOnce(r, 3000);
    std::printf("dense grid: fp64 fallback on %.2f %% of edge evaluations\n",
                100.0 * double(cov.counters.fallbacks) / double(cov.counters.edgeEvaluations));
  }
}

TEST_F(Raster3dTest, WithoutTheFp64FallbackNoEdgeIsReEvaluatedAndTheResultIsReported) {
  // The same grids in float alone. Measured on lavapipe (Mesa 25.0.7): 0 holes and 0 double
  // covers here too: a float vertex lies off its pixel's ray by its own rounding, about as far as
  // the edge functions' rounding, and here the geometry's side wins. The fallback is what makes
  // the result exact when it does not; this test only records the figures.
  const Rays rays(obliqueCamera());
  size_t holes = 0, doubles = 0;
  for (const glm::dmat4& pose : denseGridPoses()) {
    Scene s = emptyScene("grid", obliqueCamera());
    const Grid g = addGrid(s, rays, 60, 1.0, pose);
    const Coverage cov = rasterize(*ctx, s, /*fp64Fallback=*/false);
    EXPECT_EQ(cov.counters.fallbacks, 0u);
    const FillResult r = checkGrid(cov, g, rays);
    EXPECT_GT(r.inside, 3000u);
    holes += r.holes;
    doubles += r.doubleCovers;
  }
  std::printf("dense grids without the fp64 fallback: %zu holes, %zu double covers\n", holes, doubles);
}

TEST_F(Raster3dTest, QuadGridUnderRandomPerspectiveIsCoveredExactlyOnce) {
  const Rays rays(obliqueCamera());
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> angle(-1.0, 1.0), unit(-1.0, 1.0);
  for (int k = 0; k < 12; ++k) {
    SCOPED_TRACE("case " + std::to_string(k));
    // Tilt up to ±57° about a random in-plane axis, spin about the view axis, shift a little.
    const glm::dvec3 axis = glm::normalize(glm::dvec3(unit(rng), unit(rng), 0.0));
    glm::dmat4 pose = glm::translate(glm::dmat4(1.0), glm::dvec3(0.05 * unit(rng), 0.05 * unit(rng), 0.3 * unit(rng)));
    pose = glm::rotate(pose, angle(rng), axis);
    pose = glm::rotate(pose, 3.0 * angle(rng), glm::dvec3(0, 0, 1));
    Scene s = emptyScene("grid", obliqueCamera());
    const Grid g = addGrid(s, rays, 12, 4.0, pose);
    const FillResult r = checkGrid(rasterize(*ctx, s), g, rays);
    expectExactlyOnce(r, 300);
  }
}

TEST_F(Raster3dTest, FansAroundAVertexOnAPixelCentreCoverEveryPixelOnce) {
  const Rays rays(originCamera());
  for (int spokes = 3; spokes <= 12; ++spokes) {
    SCOPED_TRACE(std::to_string(spokes) + " spokes");
    Scene s = emptyScene("fan");
    const glm::dvec3 hub = 3.0 * rays.at(31, 31);  // on the centre of pixel (31, 31)
    std::vector<glm::dvec3> rim;
    for (int i = 0; i < spokes; ++i) {
      const double a = 2 * M_PI * i / spokes + 0.1;
      rim.push_back(glm::dvec3(glm::vec3(3.0 * rays.at(31 + 20 * std::cos(a), 31 + 20 * std::sin(a)))));
    }
    std::vector<glm::dvec3> tris;
    const glm::dvec3 h = glm::dvec3(glm::vec3(hub));
    for (int i = 0; i < spokes; ++i) tris.insert(tris.end(), {h, rim[i], rim[(i + 1) % spokes]});
    addTriangles(s, tris);
    const Coverage cov = rasterize(*ctx, s);
    // Pixels near the hub (within 8 px: inside the rim polygon for every spoke count >= 3,
    // whose inradius is 20·cos(π/3) = 10 px) are covered exactly once; nothing twice anywhere.
    size_t near = 0, bad = 0, twice = 0;
    for (uint32_t y = 0; y < kSize; ++y)
      for (uint32_t x = 0; x < kSize; ++x) {
        const uint32_t c = cov.count[y * kSize + x];
        twice += c >= 2;
        if (std::hypot(double(x) - 31, double(y) - 31) < 8) {
          ++near;
          bad += c != 1;
        }
      }
    EXPECT_GT(near, 150u);
    EXPECT_EQ(bad, 0u);
    EXPECT_EQ(twice, 0u);
  }
}

TEST_F(Raster3dTest, AClosedSphereIsCoveredZeroOrTwiceAtEveryPixel) {
  // A ray meets a closed convex surface twice or not at all: coverage 1 or 3 would be a crack or
  // a double cover. Where a front and a back face share a silhouette edge, both rows are the same
  // (the edge normal and the orientation both flip), so both or neither take the pixel.
  Scene s = emptyScene("sphere");
  MeshBuilder mb("sphere");
  addSphere(mb, 0, glm::translate(glm::dmat4(1.0), glm::dvec3(0.1, -0.05, -3.0)), 24, 12);
  mb.appendTo(s);
  const Coverage cov = rasterize(*ctx, s);
  size_t two = 0, odd = 0;
  for (uint32_t c : cov.count) {
    two += c == 2;
    odd += c != 0 && c != 2;
  }
  EXPECT_GT(two, 500u);
  EXPECT_EQ(odd, 0u);
}

TEST_F(Raster3dTest, DegenerateTrianglesCoverNothing) {
  const Rays rays(originCamera());
  Scene s = emptyScene("degenerate");
  const glm::dvec3 a = 2.0 * rays.at(10, 10), b = 2.0 * rays.at(50, 20);
  // A repeated vertex, three collinear points, and a triangle whose plane holds the eye (it is
  // seen edge-on: V = 0).
  addTriangles(s, {a, a, b, a, 0.5 * (a + b), b, a, 2.0 * a, b});
  const Coverage cov = rasterize(*ctx, s);
  for (uint32_t n : cov.count) ASSERT_EQ(n, 0u);
  for (uint64_t v : cov.vis) ASSERT_EQ(v, ~0ull);
}

TEST_F(Raster3dTest, ATriangleCrossingTheEyePlaneCoversExactlyWhatTheRayCastHits) {
  // One vertex behind the eye: no clipping, each pixel decided by its own ray. The double ray cast
  // (Möller-Trumbore in double on the float vertices) is the reference; pixels within 1e-6 (in
  // barycentric units) of an edge, or within 1e-6 relative of the near plane, may go either way.
  const Rays rays(originCamera());
  Scene s = emptyScene("crossing");
  const glm::dvec3 v0 = glm::dvec3(glm::vec3(-1.5, -0.4, -2.0)), v1 = glm::dvec3(glm::vec3(1.2, -0.6, -1.5)),
                   v2 = glm::dvec3(glm::vec3(0.1, 0.8, 1.0));
  addTriangles(s, {v0, v1, v2});
  const Coverage cov = rasterize(*ctx, s);
  const double zn = 0.1, zf = 100.0;
  size_t hits = 0, wrong = 0;
  for (uint32_t y = 0; y < kSize; ++y)
    for (uint32_t x = 0; x < kSize; ++x) {
      const glm::dvec3 d = rays.at(x, y);
      const glm::dvec3 e1 = v1 - v0, e2 = v2 - v0, pv = glm::cross(d, e2);
      const double det = glm::dot(e1, pv);
      const glm::dvec3 tv = -v0;
      const double u = glm::dot(tv, pv) / det;
      const glm::dvec3 qv = glm::cross(tv, e1);
      const double v = glm::dot(d, qv) / det, t = glm::dot(e2, qv) / det;
      const double margin = std::min({u, v, 1 - u - v});
      const bool ambiguous = std::abs(margin) < 1e-6 || std::abs(t - zn) < 1e-6 * zn;
      const bool hit = margin > 0 && t >= zn && t <= zf;
      const bool got = cov.vis[y * kSize + x] != ~0ull;
      hits += hit;
      if (!ambiguous) wrong += hit != got;
    }
  EXPECT_GT(hits, 200u);
  EXPECT_EQ(wrong, 0u);
}

TEST_F(Raster3dTest, BinnedEqualsBruteForceBitForBitAndTestsFewerPixels) {
  // Binning skips only tiles that no pixel centre of can be inside (tileMayBeCovered), so the
  // visibility buffer and the coverage must be identical; it must also skip something.
  const Rays rays(obliqueCamera());
  Scene grid = emptyScene("grid", obliqueCamera());
  addGrid(grid, rays, 8, 7.0, glm::rotate(glm::dmat4(1.0), 0.5, glm::dvec3(0, 0, 1)));
  AtriumParams ap;
  const Scene atrium = makeAtrium(ap);
  for (const Scene* scene : {static_cast<const Scene*>(&grid), &atrium}) {
    SCOPED_TRACE(scene->name);
    const Coverage brute = rasterize(*ctx, *scene, true, "3dr", 160, 90);
    const Coverage binned = rasterize(*ctx, *scene, true, "3dr-binned", 160, 90);
    EXPECT_EQ(binned.vis, brute.vis);
    EXPECT_EQ(binned.count, brute.count);
    EXPECT_EQ(binned.counters.covered, brute.counters.covered);
    EXPECT_LT(binned.counters.pixelsTested, brute.counters.pixelsTested);
    std::printf("%s: pixels tested %llu binned, %llu brute force\n", scene->name.c_str(),
                (unsigned long long)binned.counters.pixelsTested, (unsigned long long)brute.counters.pixelsTested);
  }
}

TEST_F(Raster3dTest, AtriumIdsAndDepthsMatchADoublePrecisionRayCast) {
  // Every pixel against the watertight double ray cast along the same rays (primary_analysis.h):
  // ids equal wherever both hit, except at ties (a ray within kTieMargin of an edge, or touching
  // surfaces); holes and spurious hits likewise only at ties; depth within 1e-6 at p99.9 (t comes
  // from two float dot products: a few u unless the ray grazes the plane).
  const Scene scene = makeAtrium(AtriumParams{});
  RenderSettings rs = atrium3drSettings();
  Renderer r(*ctx, scene, rs);
  r.renderFrame(true);
  const PrimaryComparison c =
      comparePrimary(buildBvh(scene), r.raster3d()->readVisibility(), raster3dConstants(r.camera(), 160, 90, 0, 0));
  std::printf(
      "atrium 160x90 vs ray cast: %llu both hit, %llu ids equal, %llu mismatches, %llu holes, %llu spurious, "
      "%llu not ties, depth p99.9 %.3g, max %.3g\n",
      (unsigned long long)c.bothHit, (unsigned long long)c.idsEqual, (unsigned long long)c.idMismatches,
      (unsigned long long)c.holes, (unsigned long long)c.spurious, (unsigned long long)c.notTies, c.depthRelP999,
      c.depthRelMax);
  EXPECT_GT(c.bothHit, 10000u);
  EXPECT_EQ(c.notTies, 0u);
  // The per-pixel test counts (edge_evaluations.png) add up to the frame's counter.
  uint64_t tests = 0;
  for (uint32_t n : r.raster3d()->readPixelTests()) tests += n;
  EXPECT_EQ(tests, r.raster3d()->readCounters().pixelsTested);
  EXPECT_GE(double(c.idsEqual), 0.999 * double(c.bothHit));
  EXPECT_LE(c.depthRelP999, 1e-6);
}

// far-origin: the cube scene 10 km from the world origin, where float spacing is ~1 mm. 3DR sets a
// triangle up from eye-relative vertices (raster3d.glsl.inc r3dRelative: world − eye in float,
// exact by Sterbenz where a coordinate of both lies within a factor 2 of the other, as the 10 km
// one does; the small ones round by u of their difference), so its edge functions see the same
// metre-scale numbers as at the origin. The bounds: ids equal on >= 99.999 % of the pixels
// both hit (at 320x180 no pixel may differ unless a tie), depth p99.9 <= 1e-6, 0 that are not ties;
// the same cube at the origin gives the comparison's baseline.
TEST_F(Raster3dTest, FarFromTheOriginTheCameraRelativeSetupMatchesTheDoubleRayCast) {
  for (const Scene& scene : {makeFarOrigin(), makeCube({0, 0, 0})}) {
    SCOPED_TRACE(scene.name);
    RenderSettings rs;
    rs.width = 320;
    rs.height = 180;
    rs.primary = hb::testing::primaryNamed("3dr");
    Renderer r(*ctx, scene, rs);
    r.renderFrame(true);
    const PrimaryComparison c = comparePrimary(buildBvh(scene), r.raster3d()->readVisibility(),
                                               raster3dConstants(r.camera(), rs.width, rs.height, 0, 0));
    std::printf(
        "%s 320x180 vs ray cast: %llu both hit, %llu ids equal, %llu holes, %llu spurious, %llu not ties, "
        "depth p99.9 %.3g, max %.3g\n",
        scene.name.c_str(), (unsigned long long)c.bothHit, (unsigned long long)c.idsEqual, (unsigned long long)c.holes,
        (unsigned long long)c.spurious, (unsigned long long)c.notTies, c.depthRelP999, c.depthRelMax);
    EXPECT_GT(c.bothHit, 20000u);
    EXPECT_EQ(c.notTies, 0u);
    EXPECT_GE(double(c.idsEqual), 0.99999 * double(c.bothHit));
    EXPECT_LE(c.depthRelP999, 1e-6);
  }
}

TEST_F(Raster3dTest, GeometricNormalsAreTheVisibleTrianglesOwnAndHitPositionsNeed3dr) {
  // normal_culling=geometric reads the triangle the visibility buffer names: its normal must be the
  // shading pass's reference normal of that pixel (the same triangle's face normal, computed there
  // from the drawn vertices: both are float cross products, so within a few u; 1e-4 rad allows
  // triangles 100x longer than wide).
  const Scene scene = makeAtrium(AtriumParams{});
  RenderSettings rs = atrium3drSettings();
  rs.normals = NormalCulling::Geometric;
  rs.worldPos = WorldPosMethod::Hit;
  Renderer r(*ctx, scene, rs);
  r.renderFrame(true);
  const ShadowReadback sh = shadowsOf(r)->readShadows();
  const std::vector<float> ref = r.readRefNormals();
  size_t compared = 0, off = 0;
  for (size_t i = 0; i < ref.size() / 4; ++i) {
    if (ref[4 * i + 3] != 1.0f) continue;
    const glm::dvec3 a(sh.normals[4 * i], sh.normals[4 * i + 1], sh.normals[4 * i + 2]);
    const glm::dvec3 b(ref[4 * i], ref[4 * i + 1], ref[4 * i + 2]);
    if (glm::dot(a, a) == 0.0) continue;  // degenerate: no normal, no culling
    ++compared;
    off += std::acos(std::clamp(glm::dot(a, b) / (glm::length(a) * glm::length(b)), -1.0, 1.0)) > 1e-4;
  }
  EXPECT_GT(compared, 10000u);
  EXPECT_EQ(off, 0u);
  RenderSettings hw = rs;
  hw.primary = hb::testing::primaryNamed("hardware");
  EXPECT_THROW(Renderer(*ctx, scene, hw), InputError);
}

TEST_F(Raster3dTest, VisbufferShadingMatchesTheForwardPass) {
  // shading=visbuffer shades the same triangle per pixel as the forward pass on top of 3dr, with
  // the same BRDF (shading_brdf.glsl.inc); it differs only where texture LOD comes from analytic
  // derivatives instead of 2x2-quad differences and in the order of float interpolation. So the
  // face normals (same triangle, same float ops) agree to rounding everywhere, and the image's
  // FLIP mean stays below 0.05 (the FLIP paper's threshold of a barely noticeable difference).
  AtriumParams ap;
  const Scene scene = makeAtrium(ap);
  auto renderWith = [&](bool visbuffer, std::vector<float>& normals) {
    RenderSettings rs;
    rs.width = 160;
    rs.height = 90;
    rs.primary = hb::testing::primaryNamed("3dr");
    rs.shading = (visbuffer) ? ShadingMethod::Visbuffer : ShadingMethod::Forward;
    Renderer r(*ctx, scene, rs);
    r.renderFrame(true);
    normals = r.readRefNormals();
    ImageF hdr{160, 90, 4, r.readColor()};
    return toneMapToSrgb(hdr, 0.0f, ToneMapOperator::AcesFitted).image;
  };
  std::vector<float> nForward, nVisbuffer;
  const ImageRGBA8 forward = renderWith(false, nForward), visbuffer = renderWith(true, nVisbuffer);
  // Where the hardware rasterizer's fill rule gives an edge pixel to the neighbouring triangle,
  // the forward pass has no fragment of the 3DR triangle there and leaves the pixel unshaded: the
  // visibility-buffer pass shades it. Those are counted, not compared.
  size_t valid = 0, normalsOff = 0, forwardMissed = 0;
  for (size_t i = 0; i < nForward.size() / 4; ++i) {
    if (nForward[4 * i + 3] != nVisbuffer[4 * i + 3]) {
      forwardMissed += nForward[4 * i + 3] == 0.0f && nVisbuffer[4 * i + 3] == 1.0f;
      normalsOff += !(nForward[4 * i + 3] == 0.0f && nVisbuffer[4 * i + 3] == 1.0f);
      continue;
    }
    if (nForward[4 * i + 3] != 1.0f) continue;
    ++valid;
    const glm::dvec3 a(nForward[4 * i], nForward[4 * i + 1], nForward[4 * i + 2]);
    const glm::dvec3 b(nVisbuffer[4 * i], nVisbuffer[4 * i + 1], nVisbuffer[4 * i + 2]);
    normalsOff += glm::length(a - b) > 1e-5;
  }
  const FlipResult flip = ldrFlip(forward, visbuffer);
  std::printf(
      "visbuffer vs forward shading (atrium 160x90): FLIP mean %.5f, p95 %.5f; %zu of %zu normals differ; "
      "%zu pixels the forward pass left unshaded\n",
      flip.mean, flip.p95, normalsOff, valid, forwardMissed);
  EXPECT_GT(valid, 10000u);
  EXPECT_EQ(normalsOff, 0u);
  EXPECT_LE(forwardMissed, valid / 100);
  EXPECT_LT(flip.mean, 0.05);
  RenderSettings hw;
  hw.shading = ShadingMethod::Visbuffer;
  EXPECT_THROW(Renderer(*ctx, scene, hw), InputError);
}

TEST_F(Raster3dTest, On3drEarlyDepthTestShadesExactlyWhatTheIdTestAloneShades) {
  // The shading pass on top of 3dr keeps a fragment when its triangle is the pixel's; the biased
  // early depth test in front of that must never remove the visible one. Same image, bit for bit.
  AtriumParams ap;
  const Scene scene = makeAtrium(ap);
  auto colorOf = [&](bool depthTest) {
    RenderSettings rs;
    rs.width = 160;
    rs.height = 90;
    rs.primary = hb::testing::primaryNamed("3dr");
    rs.raster3dShadingDepthTest = depthTest;
    Renderer r(*ctx, scene, rs);
    r.renderFrame(false);
    return r.readColor();
  };
  const std::vector<float> withTest = colorOf(true), idOnly = colorOf(false);
  ASSERT_EQ(withTest.size(), idOnly.size());
  size_t differ = 0, lit = 0;
  for (size_t i = 0; i < withTest.size(); i += 4) {
    differ += withTest[i] != idOnly[i] || withTest[i + 1] != idOnly[i + 1] || withTest[i + 2] != idOnly[i + 2];
    lit += idOnly[i] + idOnly[i + 1] + idOnly[i + 2] > 0.0f;
  }
  EXPECT_GT(lit, 5000u);
  EXPECT_EQ(differ, 0u);
}

TEST_F(Raster3dTest, AtriumFrameOnTopOf3drMatchesTheHardwarePrepassDepth) {
  AtriumParams ap;
  const Scene scene = makeAtrium(ap);
  auto depthOf = [&](const char* primary) {
    RenderSettings rs;
    rs.width = 160;
    rs.height = 90;
    rs.primary = hb::testing::primaryNamed(primary);
    Renderer r(*ctx, scene, rs);
    r.renderFrame(true);
    return r.readDepth();
  };
  const std::vector<float> hw = depthOf("hardware"), r3 = depthOf("3dr");
  // Both rasterizers compute the same depth of the same nearest surface up to rounding: relative
  // differences of a few u (2^-24) except where the two fill rules pick different triangles on an
  // edge, or a surface behind is within rounding of the front. Require 99 % within 1e-4.
  size_t both = 0, close = 0, skyMismatch = 0;
  for (size_t i = 0; i < hw.size(); ++i) {
    if ((hw[i] == 0.0f) != (r3[i] == 0.0f)) ++skyMismatch;
    if (hw[i] == 0.0f || r3[i] == 0.0f) continue;
    ++both;
    close += std::abs(double(hw[i]) - r3[i]) <= 1e-4 * std::abs(double(hw[i]));
  }
  EXPECT_GT(both, 10000u);
  EXPECT_GE(double(close), 0.99 * double(both));
  EXPECT_LE(skyMismatch, hw.size() / 1000);
}

// The paper's continuum through the same grids: 2dr (2D homogeneous, float only) and raycast (the
// device's ray tracer). 3dr is exact (its fp64 fallback and tie rule). raycast: the grid's inside is
// one mesh whose every inner edge is shared by two consistently wound triangles and whose inner
// vertices are closed fans; the Vulkan spec (Ray Traversal, "Watertightness") says implementations
// should not miss a ray that meets such an edge or vertex, and docs/numerics.md claims watertight
// GPU rays (the cube's shared edges): 0 holes (a ray cast reports one hit per pixel, so a double
// hit cannot show). 2dr: no fallback, so its count may differ from the exact one where its rounding
// allows (raster2dRoundingBand: near vertices and unshared edges) and nowhere else; these grids'
// vertices lie on pixel corners (addGrid) and every centre on a cell's diagonal, a shared edge
// alone, so the band is empty and 2dr must be exact here.
TEST_F(Raster3dTest, TheContinuumOnTheDenseGridsStaysWithinWhatEachMethodDerives) {
  const Rays rays(obliqueCamera());
  for (const char* primary : {"3dr", "2dr", "raycast"}) {
    size_t holes = 0, doubles = 0, inside = 0, outsideBand = 0, bandPixels = 0;
    for (const glm::dmat4& pose : denseGridPoses()) {
      Scene s = emptyScene("grid", obliqueCamera());
      const Grid g = addGrid(s, rays, 60, 1.0, pose);
      const Coverage cov = rasterize(*ctx, s, true, primary);
      const FillResult r = checkGrid(cov, g, rays);
      EXPECT_EQ(r.spill, 0u) << primary;
      inside += r.inside;
      holes += r.holes;
      doubles += r.doubleCovers;
      if (std::string(primary) == "2dr") {
        const std::vector<uint8_t> band = raster2dRoundingBand(s, rays.c);
        const CoverageComparison c = compareCoverage(s, rays.c, cov.count, &band);
        outsideBand += c.outsideBand;
        bandPixels += c.bandPixels;
      }
    }
    EXPECT_GT(inside, 9000u);
    if (std::string(primary) != "2dr") {
      EXPECT_EQ(holes, 0u) << primary;
    }
    if (std::string(primary) == "3dr") {
      EXPECT_EQ(doubles, 0u);
    }
    EXPECT_EQ(outsideBand, 0u) << primary << ": coverage errors where its rounding cannot make them";
    std::printf("dense grids, %s: %zu holes, %zu double covers of %zu inside pixels", primary, holes, doubles, inside);
    if (std::string(primary) == "2dr")
      std::printf("; %zu pixels in its rounding band, %zu errors outside", bandPixels, outsideBand);
    std::printf("\n");
  }
}

TEST_F(Raster3dTest, RaycastGivesTheSameIdsAndDepthsAsTheDoubleRayCastAnd3dr) {
  // primary=raycast traces the same float rays on the TLAS (the driver's) or on our BVH
  // (backend=compute): the nearest hit's triangle id must map back to the draw-order id (the
  // instance/geometry/primitive table; ours carries it in the triangle), so wherever the exact ray
  // cast hits, ids agree except at ties, and depth within the ray tracer's own error (a few u of t,
  // the same 1e-6 at p99.9 as 3dr). The two backends name the same triangle at every pixel but ties.
  const Scene scene = makeAtrium(AtriumParams{});
  std::map<std::pair<RtBackend, uint32_t>, std::vector<uint64_t>> byBackend;
  for (auto [backend, width] :
       {std::pair{RtBackend::Auto, 2u}, {RtBackend::Compute, 2u}, {RtBackend::Compute, 4u}, {RtBackend::Compute, 8u}}) {
    SCOPED_TRACE(std::string(toString(backend)) + ", bvh_width " + std::to_string(width));
    RenderSettings rs = atrium3drSettings();
    rs.primary = hb::testing::primaryNamed("raycast");
    rs.backend = backend;
    rs.bvhWidth = width;
    Renderer r(*ctx, scene, rs);
    r.renderFrame(true);
    EXPECT_EQ(r.passesRun().front(), "raycast");
    EXPECT_EQ(r.traceBvh() != nullptr, backend == RtBackend::Compute);
    const std::vector<uint64_t> cast = r.raster3d()->readVisibility();
    const PrimaryComparison c = comparePrimary(buildBvh(scene), cast, raster3dConstants(r.camera(), 160, 90, 0, 0));
    EXPECT_GT(c.bothHit, 10000u);
    EXPECT_EQ(c.holes, 0u);
    EXPECT_EQ(c.spurious, 0u);
    EXPECT_EQ(c.notTies, 0u);
    EXPECT_GE(double(c.idsEqual), 0.999 * double(c.bothHit));
    EXPECT_LE(c.depthRelP999, 1e-6);
    const Coverage r3 = rasterize(*ctx, scene, true, "3dr", 160, 90);
    size_t same = 0, hit = 0;
    for (size_t i = 0; i < cast.size(); ++i) {
      if (cast[i] == ~0ull && r3.vis[i] == ~0ull) continue;
      ++hit;
      same += uint32_t(cast[i]) == uint32_t(r3.vis[i]);
    }
    EXPECT_GE(double(same), 0.999 * double(hit));
    std::printf(
        "atrium 160x90, backend=%s, bvh_width %u: raycast and 3dr name the same triangle at %zu of %zu pixels\n",
        toString(backend), width, same, hit);
    byBackend[{backend, width}] = cast;
  }
  // Every width tests the same triangles to the same closest hit, ties to the lower id: equal.
  EXPECT_TRUE((byBackend[{RtBackend::Compute, 2u}] == byBackend[{RtBackend::Compute, 4u}]));
  EXPECT_TRUE((byBackend[{RtBackend::Compute, 2u}] == byBackend[{RtBackend::Compute, 8u}]));
  const std::vector<uint64_t>&driver = byBackend[{RtBackend::Auto, 2u}], &ours = byBackend[{RtBackend::Compute, 2u}];
  ASSERT_EQ(driver.size(), ours.size());
  size_t idsDiffer = 0, hitDiffers = 0;
  for (size_t i = 0; i < driver.size(); ++i) {
    hitDiffers += (driver[i] == ~0ull) != (ours[i] == ~0ull);
    idsDiffer += driver[i] != ~0ull && ours[i] != ~0ull && uint32_t(driver[i]) != uint32_t(ours[i]);
  }
  EXPECT_EQ(hitDiffers, 0u);  // watertight both: a pixel hit by one is hit by the other
  // Different ids only at ties (the double ray cast's notTies is 0 for both): a handful of pixels.
  EXPECT_LE(double(idsDiffer), 0.001 * double(driver.size()));
  std::printf("atrium 160x90: the driver's and our BVH name different triangles at %zu pixels (ties)\n", idsDiffer);
}

TEST_F(Raster3dTest, TwoDHomogeneousRasterizationAgreesWith3drUpToItsRounding) {
  // 2dr's coverage is float-only 2D homogeneous edge functions and its depth is W = det/ΣE: the
  // coverage check counts what that costs (double covers, holes), which must lie in the band its
  // rounding allows (raster2dRoundingBand, derived in primary_analysis.cpp); the visible triangle must still
  // be 3dr's on almost every pixel (a wrong id needs two surfaces within 2dr's depth error, a few
  // percent at worst, measured 0.86 % of pixels at 320x180; 95 % leaves room for a smaller frame).
  const Scene scene = makeAtrium(AtriumParams{});
  const Coverage two = rasterize(*ctx, scene, true, "2dr", 160, 90);
  const Coverage three = rasterize(*ctx, scene, true, "3dr", 160, 90);
  size_t same = 0, hit = 0;
  for (size_t i = 0; i < two.vis.size(); ++i) {
    if (two.vis[i] == ~0ull && three.vis[i] == ~0ull) continue;
    ++hit;
    same += uint32_t(two.vis[i]) == uint32_t(three.vis[i]);
  }
  EXPECT_GT(hit, 10000u);
  EXPECT_GE(double(same), 0.95 * double(hit));
  EXPECT_EQ(two.counters.fallbacks, 0u);  // the baseline has no fp64 re-evaluation
  const gpu::Raster3dConstants rays = raster3dConstants(scene.cameras[0], 160, 90, 0, 0);
  const CoverageComparison c3 = compareCoverage(scene, rays, three.count);
  // 2dr's double covers and holes: only where its rounding allows them (raster2dRoundingBand).
  const std::vector<uint8_t> band = raster2dRoundingBand(scene, rays);
  const CoverageComparison c2 = compareCoverage(scene, rays, two.count, &band);
  EXPECT_EQ(c3.doubleCovers, 0u);  // 3dr against the exact CPU rasterization: nothing claimed twice
  EXPECT_EQ(c3.holes, 0u);
  EXPECT_EQ(c2.outsideBand, 0u) << "2dr coverage errors where its rounding cannot make them";
  std::printf(
      "atrium 160x90: 2dr names 3dr's triangle at %zu of %zu pixels; coverage vs exact: 2dr %llu double "
      "covers, %llu holes (%llu pixels in its rounding band, %llu errors outside it); 3dr %llu, %llu\n",
      same, hit, (unsigned long long)c2.doubleCovers, (unsigned long long)c2.holes, (unsigned long long)c2.bandPixels,
      (unsigned long long)c2.outsideBand, (unsigned long long)c3.doubleCovers, (unsigned long long)c3.holes);
}

// 2dr where its derivation says it is exact: a shared edge alone. Grids with a vertex on every
// other pixel centre (step 2, shifted onto centres) put the centres between them on the shared
// edges (the edge midpoints and the cells' diagonals: the grid is fronto-parallel, so it projects
// affinely), within the vertices' own rounding; so do the dense grids above (vertices on corners,
// centres on the diagonals). There the two triangles' rows are exact negations (raster3d.glsl.inc
// r2dSetup) and the centre must go to exactly one of them, however the rounding falls. Only the
// vertex pixels (a quarter of the grid) and the outline may differ (raster2dRoundingBand); the band
// must leave the edge pixels out, so that the test can see an error there.
TEST_F(Raster3dTest, TwoDHomogeneousCoverageIsExactOnSharedEdgesAndDiffersOnlyInItsRoundingBand) {
  const Rays rays(obliqueCamera());
  for (const glm::dmat4& pose : denseGridPoses()) {
    Scene s = emptyScene("grid", obliqueCamera());
    const Grid g = addGrid(s, rays, 30, 2.0, pose, 0.5);
    const Coverage cov = rasterize(*ctx, s, true, "2dr");
    const FillResult r = checkGrid(cov, g, rays);
    const std::vector<uint8_t> band = raster2dRoundingBand(s, rays.c);
    const CoverageComparison c = compareCoverage(s, rays.c, cov.count, &band);
    std::printf(
        "step-2 grid, 2dr: %zu holes, %zu double covers of %zu inside pixels; %llu pixels in its rounding band, "
        "%llu errors outside it\n",
        r.holes, r.doubleCovers, r.inside, (unsigned long long)c.bandPixels, (unsigned long long)c.outsideBand);
    EXPECT_GT(r.inside, 3000u);
    EXPECT_EQ(r.spill, 0u);
    EXPECT_EQ(c.outsideBand, 0u);
    // 31² vertices and an outline ring of 4 x 60 pixels (a few wide at most): well under half the
    // 3,600 grid pixels, so at least half lie on shared edges alone.
    EXPECT_LT(c.bandPixels, r.inside / 2);
  }
}

// ---- raycast and 3dr on shared edges and vertices exactly on the rays -------------------------------

// An orthographic view whose pixel-centre rays are exact in float: 64 x 64 pixels over [−32, 32]²
// from an eye at the origin looking down −z, so raster3dConstants gives origin0 = (−31.5, 31.5, 0),
// originX = (1, 0, 0), originY = (0, −1, 0) and pixel (x, y)'s ray starts at (x − 31.5, 31.5 − y, 0)
// along −z: every operation on them is exact, in the shaders, the ray tracer's ray setup and here.
Camera exactOrthoCamera() {
  Camera cam = originCamera();
  cam.projection = CameraProjection::Orthographic;
  cam.xmag = 32.0f;
  cam.ymag = 32.0f;
  return cam;
}

// A lattice of vertices on pixel centres, vertex (i, j) at pixel (step·(i + shear·j), step·j), tilted
// in depth, two triangles per cell (alternating diagonals, wound consistently), reaching 4 pixels
// beyond the image on every side so that no outline edge is seen. Its edges' and vertices' x and y
// are small integers and halves, exact in float, so a pixel centre on an edge or vertex is exactly
// on it for the ray tracer's watertight test and 3DR's edge functions alike: every edge value there
// is an exact 0, decided by the implementation's tie rule alone. Returns each triangle's corners in
// pixel coordinates (draw order = triangle id).
std::vector<std::array<glm::ivec2, 3>> addExactLattice(Scene& s, int step, int shear) {
  auto world = [&](glm::ivec2 q) {
    const double x = q.x - 31.5, y = 31.5 - q.y;
    return glm::dvec3(x, y, -(3.0 + 0.013 * x + 0.021 * y));
  };
  std::vector<glm::dvec3> corners;
  std::vector<std::array<glm::ivec2, 3>> tris;
  const int jLo = -4 / step - 1, jHi = 68 / step + 1;
  for (int j = jLo; j <= jHi; ++j) {
    const int iLo = (-4 - step * shear * j) / step - 2, iHi = (68 - step * shear * j) / step + 2;
    for (int i = iLo; i <= iHi; ++i) {
      auto at = [&](int a, int b) { return glm::ivec2(step * (a + shear * b), step * b); };
      const glm::ivec2 a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      // Every triangle runs the same way round (a, b, c are in order around the cell), so the two
      // triangles of each edge run it in opposite directions: the spec's consistent winding.
      const std::array<std::array<glm::ivec2, 3>, 2> cell =
          (i + j) % 2 == 0 ? std::array<std::array<glm::ivec2, 3>, 2>{{{a, b, c}, {a, c, d}}}
                           : std::array<std::array<glm::ivec2, 3>, 2>{{{a, b, d}, {b, c, d}}};
      for (const auto& t : cell) {
        tris.push_back(t);
        for (const glm::ivec2& q : t) corners.push_back(world(q));
      }
    }
  }
  addTriangles(s, corners);
  return tris;
}

// Is the pixel centre q in the closed triangle t (integer pixel coordinates, exact)?
bool inClosedTriangle(const std::array<glm::ivec2, 3>& t, glm::ivec2 q) {
  int64_t sign[3];
  for (int i = 0; i < 3; ++i) {
    const glm::ivec2 a = t[i], b = t[(i + 1) % 3];
    sign[i] = int64_t(b.x - a.x) * (q.y - a.y) - int64_t(b.y - a.y) * (q.x - a.x);
  }
  return (sign[0] >= 0 && sign[1] >= 0 && sign[2] >= 0) || (sign[0] <= 0 && sign[1] <= 0 && sign[2] <= 0);
}

// Is the pixel centre q on an edge of t (collinear with it and between its ends)?
bool onTriangleEdge(const std::array<glm::ivec2, 3>& t, glm::ivec2 q) {
  for (int i = 0; i < 3; ++i) {
    const glm::ivec2 a = t[i], b = t[(i + 1) % 3];
    const int64_t cross = int64_t(b.x - a.x) * (q.y - a.y) - int64_t(b.y - a.y) * (q.x - a.x);
    if (cross == 0 && q.x >= std::min(a.x, b.x) && q.x <= std::max(a.x, b.x) && q.y >= std::min(a.y, b.y) &&
        q.y <= std::max(a.y, b.y))
      return true;
  }
  return false;
}

// The Vulkan spec's watertightness (Ray Traversal, "Watertightness": implementations should not
// double-hit or miss when a ray intersects a shared edge, or a shared vertex of a closed fan) and
// the claim docs/numerics.md makes of the GPU's rays, where it can fail: every pixel's ray passes
// exactly through a shared edge or vertex of a closed, consistently wound lattice that fills the
// view (step 1: a vertex on every centre; step 2: vertices on every other, edges through the rest;
// sheared: edges of slope 1 and 1/2 as well). The ray cast must hit at every pixel (0 holes), name a
// triangle that holds the centre, and agree with the double ray cast (0 holes, 0 spurious, 0 not
// ties). 3dr, whose tie rule claims each such centre for exactly one triangle, must cover every
// pixel exactly once.
TEST_F(Raster3dTest, RaysThroughSharedEdgesAndVerticesExactlyAreNeitherMissedNorCoveredTwice) {
  struct LatticeCase {
    int step, shear;
  };
  for (const LatticeCase lc : {LatticeCase{1, 0}, LatticeCase{2, 0}, LatticeCase{2, 1}, LatticeCase{3, 1}}) {
    SCOPED_TRACE("step " + std::to_string(lc.step) + ", shear " + std::to_string(lc.shear));
    Scene s = emptyScene("exact lattice", exactOrthoCamera());
    const std::vector<std::array<glm::ivec2, 3>> tris = addExactLattice(s, lc.step, lc.shear);
    const gpu::Raster3dConstants c = raster3dConstants(s.cameras[0], kSize, kSize, 0, 0);
    ASSERT_EQ(glm::vec3(c.origin0), glm::vec3(-31.5f, 31.5f, 0.0f));  // the exact rays above
    ASSERT_EQ(glm::vec3(c.originX), glm::vec3(1.0f, 0.0f, 0.0f));
    ASSERT_EQ(glm::vec3(c.originY), glm::vec3(0.0f, -1.0f, 0.0f));
    size_t onEdges = 0;  // pixels whose centre is exactly on an edge or vertex
    for (uint32_t y = 0; y < kSize; ++y)
      for (uint32_t x = 0; x < kSize; ++x)
        onEdges +=
            std::any_of(tris.begin(), tris.end(), [&](const auto& t) { return onTriangleEdge(t, glm::ivec2(x, y)); });
    std::map<std::string, Coverage> got;
    for (const char* primary : {"raycast", "raycast-compute", "3dr"}) {  // raycast through our BVH too
      const bool compute = std::string(primary) == "raycast-compute";
      RenderSettings rs;
      rs.width = kSize;
      rs.height = kSize;
      rs.primary = hb::testing::primaryNamed(compute ? "raycast" : primary);
      rs.backend = compute ? RtBackend::Compute : RtBackend::Auto;
      rs.shading = ShadingMethod::Visbuffer;  // what an orthographic view needs (renderer.cpp)
      rs.lightCulling = false;
      rs.effects.add(EffectSource::Config, "test", {{"shadows", false}});
      Renderer r(*ctx, s, rs);
      r.renderFrame(true);
      got[primary] = {r.raster3d()->readCoverage(), r.raster3d()->readVisibility(), r.raster3d()->readCounters()};
    }
    for (const char* castName : {"raycast", "raycast-compute"}) {
      SCOPED_TRACE(castName);
      const Coverage& cast = got[castName];
      size_t missed = 0, wrongTriangle = 0, notOnce = 0;
      for (uint32_t y = 0; y < kSize; ++y)
        for (uint32_t x = 0; x < kSize; ++x) {
          const size_t i = size_t(y) * kSize + x;
          notOnce += got["3dr"].count[i] != 1u;
          if (cast.vis[i] == ~0ull) {
            ++missed;
            continue;
          }
          const uint32_t id = uint32_t(cast.vis[i]);
          wrongTriangle += id >= tris.size() || !inClosedTriangle(tris[id], glm::ivec2(x, y));
        }
      const PrimaryComparison cmp = comparePrimary(buildBvh(s), cast.vis, c);
      std::printf(
          "exact lattice step %d shear %d (%zu triangles): %zu of %u centres exactly on an edge or vertex; %s "
          "%zu missed, %zu on another triangle, vs double ray cast %llu holes %llu spurious %llu not ties; 3dr %zu "
          "pixels not covered exactly once\n",
          lc.step, lc.shear, tris.size(), onEdges, kSize * kSize, castName, missed, wrongTriangle,
          (unsigned long long)cmp.holes, (unsigned long long)cmp.spurious, (unsigned long long)cmp.notTies, notOnce);
      EXPECT_GT(onEdges, size_t(kSize * kSize) / 2);  // the case exercises exact ties (step 3: 3,193 of 4,096)
      EXPECT_EQ(missed, 0u);
      EXPECT_EQ(wrongTriangle, 0u);
      EXPECT_EQ(cmp.bothHit, uint64_t(kSize) * kSize);
      EXPECT_EQ(cmp.holes, 0u);
      EXPECT_EQ(cmp.spurious, 0u);
      EXPECT_EQ(cmp.notTies, 0u);
      EXPECT_EQ(notOnce, 0u);
    }
  }
}

TEST_F(Raster3dTest, EachDispatchIsTimedInsideItsPass) {
  const Scene scene = makeAtrium(AtriumParams{});
  for (const char* primary : {"3dr", "3dr-binned", "raycast"}) {
    RenderSettings rs = atrium3drSettings();
    rs.primary = hb::testing::primaryNamed(primary);
    rs.effects.add(EffectSource::Config, "test", {{"shadows", false}});
    Renderer r(*ctx, scene, rs);
    const FrameTiming t = r.renderFrame(false);
    std::vector<std::string> names;
    for (const auto& [name, ms] : t.passMs) names.push_back(name);
    const std::string pass = std::string(primary) == "raycast" ? "raycast" : "raster3d";
    std::vector<std::string> expected = {pass};
    if (pass == "raster3d") expected.push_back("raster3d.triangles");
    if (std::string(primary) == "3dr-binned")
      for (const char* sub : {"raster3d.count", "raster3d.scan", "raster3d.fill"}) expected.push_back(sub);
    if (pass == "raster3d") expected.push_back("raster3d.tiles");
    expected.push_back(pass + ".resolve");
    expected.push_back(pass + ".depth_copy");
    expected.push_back("light_culling");
    expected.push_back("shading");
    EXPECT_EQ(names, expected) << primary;
  }
}

}  // namespace
}  // namespace hb
