// CPU-only tests of primary_analysis's rounding band of 2D homogeneous rasterization
// (raster2dRoundingBand): which pixel centres it lets 2dr's count differ at, on two triangles whose
// edges pass through pixel centres (the GPU's counts against it: tests/raster3d_fill_rule_gpu_test.cpp).
#include "analysis/primary_analysis.h"

#include <vector>

#include <gtest/gtest.h>

#include "frame/passes/raster3d.h"
#include "scene/camera.h"

namespace hb {
namespace {

constexpr uint32_t kBandSize = 64;

// A camera off every axis (so that no product is exact by accident), 64 x 64 pixels.
Camera bandCamera() {
  Camera cam;
  cam.view = lookAt(glm::vec3(1.37f, 0.71f, 2.13f), glm::vec3(-0.4f, 0.2f, -1.9f), glm::vec3(0.1f, 1.0f, 0.05f));
  cam.yfov = 1.0f;
  cam.znear = 0.1f;
  cam.zfar = 100.0f;
  return cam;
}

// Triangles given by their corners' pixel coordinates, at view depth 2 on the pixel-centre rays
// (rounded to float once, as a scene stores them).
Scene bandScene(const gpu::Raster3dConstants& c, const std::vector<glm::dvec2>& corners) {
  Scene s;
  s.name = "band";
  s.materials.push_back({});
  s.cameras.push_back(bandCamera());
  for (const glm::dvec2& q : corners) {
    const glm::dvec3 d = glm::dvec3(c.rayD0) + q.x * glm::dvec3(c.rayDx) + q.y * glm::dvec3(c.rayDy);
    s.indices.push_back(uint32_t(s.vertices.size()));
    s.vertices.push_back({glm::vec3(glm::dvec3(c.eye) + 2.0 * d), glm::vec3(0, 0, 1), glm::vec2(0)});
  }
  s.meshes.push_back({"band", {{0, uint32_t(corners.size()), 0, uint32_t(corners.size()), 0}}});
  s.instances.push_back({0, glm::mat4(1.0f)});
  return s;
}

bool inBand(const std::vector<uint8_t>& band, int x, int y) { return band[size_t(y) * kBandSize + x] != 0; }

// The square (10, 10)-(20, 20) cut along its diagonal from (20, 10) to (10, 20), wound alike, so that
// the diagonal is shared and its two rows are exact negations in 2dr: the centre (15, 15) on it is
// decided as exactly, however the rounding falls; the corners and the outline's centres are not.
TEST(Raster2dRoundingBand, ASharedEdgeAloneIsExactWhileVerticesAndUnsharedEdgesAreNot) {
  const gpu::Raster3dConstants c = raster3dConstants(bandCamera(), kBandSize, kBandSize, 0, 0);
  const glm::dvec2 a(10, 10), b(20, 10), cc(10, 20), d(20, 20);
  const std::vector<uint8_t> both = raster2dRoundingBand(bandScene(c, {a, b, cc, b, d, cc}), c);
  EXPECT_FALSE(inBand(both, 15, 15));  // on the shared diagonal only
  EXPECT_FALSE(inBand(both, 12, 18));  // likewise, nearer one end
  EXPECT_TRUE(inBand(both, 10, 10));   // a corner (on two unshared edges)
  EXPECT_TRUE(inBand(both, 20, 10));   // an end of the shared edge: four edges meet there
  EXPECT_TRUE(inBand(both, 15, 10));   // on an unshared edge
  EXPECT_FALSE(inBand(both, 13, 13));  // inside, far from every edge
  EXPECT_FALSE(inBand(both, 40, 40));  // outside, far from every edge
  // The band is narrow: the outline's 4 x 11 centres and a few around the corners at most.
  size_t count = 0;
  for (uint8_t v : both) count += v;
  EXPECT_LE(count, 4u * 11u + 4u * 8u);
  // Without its partner the diagonal is an outline like the others: its centres join the band.
  const std::vector<uint8_t> one = raster2dRoundingBand(bandScene(c, {a, b, cc}), c);
  EXPECT_TRUE(inBand(one, 15, 15));
  EXPECT_TRUE(inBand(one, 12, 18));
  EXPECT_FALSE(inBand(one, 13, 13));
}

}  // namespace
}  // namespace hb
