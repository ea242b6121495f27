// 3D rasterization's work list when it is full (shaders/raster3d.comp.glsl PASS 0): a triangle
// whose items do not fit rasterizes its own box, and the slots it took but could not fill must not
// be read as items. Before the fix they kept whatever an earlier frame had left there, so the
// next dispatch tested that (triangle, tile) pair again: coverage counted twice in brute force,
// and in binned mode an item filled into a tile whose count did not include it. Visibility stayed
// right (atomicMin of the same key twice), so only the coverage check showed it, differently from
// run to run as the order of the atomics changed. Here the list is seeded with such a stale item
// before the frame, so that the failure does not depend on the order.
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "analysis/primary_analysis.h"
#include "frame/passes/raster3d.h"
#include "frame/renderer.h"
#include "gpu_fixture.h"

namespace hb {
namespace {

constexpr uint32_t kListSize = 64;  // 64 x 64 pixels: 64 tiles of 8 x 8, so 64 list entries at 1 a tile

// Triangle 0: a small right triangle (a box its own thread rasterizes) whose right angle is its
// box's top-left corner, so the first 8x8 tile of its box holds all its pixels; then twelve
// triangles at the back whose boxes span 3 tiles a side: 108 items for a list of 64.
Scene stalePairScene() {
  Scene s;
  s.name = "full-list";
  s.materials.push_back({});
  Camera cam;
  cam.view = glm::mat4(1.0f);  // the eye at the origin, looking down -z
  cam.yfov = 1.0f;
  cam.znear = 0.1f;
  cam.zfar = 100.0f;
  s.cameras.push_back(cam);
  // 58.5 px a metre at z = -1 (64 px over 2 tan 0.5): triangle 0 is 3.5 px a side at the top left.
  std::vector<glm::vec3> corners{{-0.50f, 0.50f, -1.0f}, {-0.50f, 0.44f, -1.0f}, {-0.44f, 0.50f, -1.0f}};
  // Twelve of 0.9 m a side at z = -3 - k/100: boxes of ~ 18 px, 3 x 3 tiles each in brute force,
  // so that 7 x 9 = 63 items leave the eighth triangle straddling the end of the list (a sum that
  // reached 64 exactly would leave no slot unfilled).
  for (int k = 0; k < 12; ++k) {
    const float x = -1.4f + 0.25f * float(k % 4), y = 1.2f - 0.5f * float(k / 4), z = -3.0f - 0.01f * float(k);
    corners.insert(corners.end(), {{x, y, z}, {x, y - 0.9f, z}, {x + 0.9f, y - 0.9f, z}});
  }
  for (size_t i = 0; i < corners.size(); ++i) {
    s.vertices.push_back({corners[i], glm::vec3(0, 0, 1), glm::vec2(0)});
    s.indices.push_back(uint32_t(i));
  }
  s.meshes.push_back({"mesh", {{0, uint32_t(corners.size()), 0, uint32_t(corners.size()), 0}}});
  s.instances.push_back({0, glm::mat4(1.0f)});
  return s;
}

class Raster3dListTest : public testing::GpuTest {};

TEST_F(Raster3dListTest, SlotsOfAFullListAreNeverReadAsAnEarlierFramesItems) {
  const Scene scene = stalePairScene();
  for (const char* method : {"3dr", "3dr-binned"}) {
    SCOPED_TRACE(method);
    RenderSettings rs;
    rs.width = rs.height = kListSize;
    rs.primary = testing::primaryNamed(method);
    rs.raster3dListPerTile = 1;
    rs.raster3dListGrows = false;  // the full list is what is tested
    rs.effects.add(EffectSource::Config, "test", {{"shadows", false}});
    Renderer r(*ctx, scene, rs);
    // What an earlier frame may have left in every slot: the item (triangle 0, first tile of its
    // box; binned: screen tile 0, where triangle 0 lies), both covering triangle 0's pixels.
    ctx->submitAndWait([&](VkCommandBuffer cmd) {
      vkCmdFillBuffer(cmd, r.raster3d()->workList().handle(), 0, VK_WHOLE_SIZE, 0);
      vkCmdFillBuffer(cmd, r.raster3d()->spans().handle(), 0, VK_WHOLE_SIZE, 0);
    });
    r.renderFrame(true);
    const Raster3dCounters counters = r.raster3d()->readCounters();
    const CoverageComparison c =
        compareCoverage(scene, raster3dConstants(r.camera(), kListSize, kListSize, 0, 0), r.raster3d()->readCoverage());
    std::printf(
        "%s, list of %u entries: %llu big triangles, %llu found it full; %llu pixels covered, %llu double "
        "covers, %llu holes\n",
        method, kListSize, (unsigned long long)counters.bigTriangles, (unsigned long long)counters.listOverflows,
        (unsigned long long)c.coveredPixels, (unsigned long long)c.doubleCovers, (unsigned long long)c.holes);
    EXPECT_EQ(counters.bigTriangles, 12u);
    EXPECT_GT(counters.listOverflows, 0u) << "the list must be full for some triangle";
    EXPECT_GT(c.coveredPixels, 500u);
    EXPECT_EQ(c.doubleCovers, 0u);
    EXPECT_EQ(c.holes, 0u);
  }
}

}  // namespace
}  // namespace hb
