// The 3D rasterization tests' scenes and checks (raster3d_*_gpu_test.cpp): square views of kSize
// pixels, the pass's pixel-centre rays in double, grids of quads whose exact coverage is known, and
// the coverage, visibility and counters of one frame.
#pragma once
#include <cmath>
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "analysis/primary_analysis.h"
#include "frame/passes/raster3d.h"
#include "frame/renderer.h"
#include "gpu_fixture.h"
#include "triangle_scenes.h"

// A named namespace: the tests build in unity batches, where anonymous namespaces of several files meet.
namespace hb::raster3d_test {

using testing::addTriangles;
using testing::emptyScene;
using testing::obliqueCamera;
using testing::originCamera;

inline constexpr uint32_t kSize = 64;

// The pixel-centre ray of the 3DR pass, in double from the same float constants.
struct Rays {
  gpu::Raster3dConstants c;
  explicit Rays(const Camera& cam) : c(raster3dConstants(cam, kSize, kSize, 0, 0)) {}
  glm::dvec3 at(double x, double y) const {  // eye-relative
    return glm::dvec3(c.rayD0) + x * glm::dvec3(c.rayDx) + y * glm::dvec3(c.rayDy);
  }
  glm::dvec3 eye() const { return glm::dvec3(c.eye); }
};

struct Coverage {
  std::vector<uint32_t> count;
  std::vector<uint64_t> vis;
  Raster3dCounters counters;
};

inline Coverage rasterize(const VulkanContext& ctx, const Scene& scene, bool fp64Fallback = true,
                          const char* primary = "3dr", uint32_t width = kSize, uint32_t height = kSize) {
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
inline Grid addGrid(Scene& s, const Rays& rays, int n, double step, const glm::dmat4& pose, double shift = 0.0) {
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
inline glm::dvec2 gridCoordinates(const Grid& g, const glm::dvec3& dir) {
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
inline FillResult checkGrid(const Coverage& cov, const Grid& g, const Rays& rays) {
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
inline void expectExactlyOnce(const FillResult& r, size_t minInside) {
  EXPECT_GT(r.inside, minInside);
  EXPECT_EQ(r.holes, 0u);
  EXPECT_EQ(r.doubleCovers, 0u);
  EXPECT_EQ(r.spill, 0u);
}

// The atrium tests' frame: 160x90 on top of 3dr.
inline RenderSettings atrium3drSettings() {
  RenderSettings rs;
  rs.width = 160;
  rs.height = 90;
  rs.primary = hb::testing::primaryNamed("3dr");
  return rs;
}

// The worst case of the CPU trial: a vertex on every pixel centre (60 x 60 quads, step
// 1 px, no rotation), and the same at a small rotation and at a quarter-pixel offset.
inline std::vector<glm::dmat4> denseGridPoses() {
  return {glm::dmat4(1.0), glm::rotate(glm::dmat4(1.0), 0.003, glm::dvec3(0, 0, 1)),
          glm::rotate(glm::dmat4(1.0), M_PI / 2, glm::dvec3(0, 0, 1))};
}

class Raster3dTest : public testing::GpuTest {};

}  // namespace hb::raster3d_test
