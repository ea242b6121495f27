// The margins of the timed frames' fast paths (raster3d_tiles.glsl.inc, and the per-triangle pass's
// small boxes, rasterizeBox in raster3d_common.glsl.inc: a pixel whose float edge values clear the
// rounding bound is decided without the exact test; with shared sample planes, all planes at once
// by the extremes of their rows) on the CPU reference's hardest grids: 100 x 100
// quads with a vertex on every pixel centre, lifted onto tilted planes under random perspectives
// (src/reference/raster3d_ref_test.cpp's dense grids), where the float edge values alone give many
// pixels to the wrong triangle. Every plane of a timed frame must hold the exact CPU rasterization's
// keys there, so a margin too small (or a fast path that skips the exact test) fails here, where
// the other scenes' pixels all lie far from their edges' rounding. Brute force with a thread box of
// 1 sends every pixel through its item pass, which has no fast path today: the case guards one
// added there (with such a path and its bound zeroed, 5,557 pixels of the first grid differed).
#include <cmath>
#include <cstdint>
#include <random>
#include <span>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "analysis/primary_analysis.h"
#include "frame/passes/aa_samples.h"
#include "raster3d_test_scenes.h"
#include "reference/raster3d_ref.h"
#include "reference/raster3d_ref_test_util.h"

namespace hb::raster3d_test {
namespace {

TEST_F(Raster3dTest, TimedFastPathsKeepTheExactKeysWhereFloatsAloneFail) {
  constexpr uint32_t w = 128, h = 128;
  std::mt19937 rng(1234);  // the CPU reference's dense grids' seed
  size_t floatsWrong = 0, hits = 0;
  for (int k = 0; k < 3; ++k) {
    SCOPED_TRACE("grid " + std::to_string(k));
    const Camera cam = randomCamera(rng);
    const Raster3dView view = raster3dViewOf(raster3dConstants(cam, w, h, 0, 64, 64));
    const PixelMesh grid = quadGrid(100, 1.0, (k % 4) * M_PI / 2, {63.5, 63.5}, true);
    const Mesh mesh = liftOntoPlane(view, grid, 3.0, (k % 5) * 0.3, rng);
    std::vector<glm::vec3> corners;
    std::vector<uint32_t> order;
    for (uint32_t i : mesh.indices) {
      order.push_back(uint32_t(corners.size()));
      corners.push_back(mesh.positions[i]);
    }
    Scene scene = emptyScene("dense-grid", cam);
    addTriangles(scene, corners);
    // The case is hard: floats alone give some pixel centre another key than the exact test.
    Raster3dSettings floatsAlone;
    floatsAlone.fp64Fallback = false;
    const Raster3dResult exact0 = rasterize3d(view, corners, order);
    const Raster3dResult plain = rasterize3d(view, corners, order, floatsAlone);
    for (size_t i = 0; i < exact0.visibility.size(); ++i) floatsWrong += plain.visibility[i] != exact0.visibility[i];

    // The binned tile pass and the small boxes (the default thread box), with and without shared
    // sample planes; and brute force with a thread box of 1, whose item pass takes every pixel.
    struct Case {
      const char* primary;
      AntiAliasing aa;
      uint32_t threadBox;
    };
    for (const Case& c : {Case{"3dr-binned", AntiAliasing::None, RenderSettings{}.raster3dThreadBox},
                          Case{"3dr-binned", AntiAliasing::Msaa16, RenderSettings{}.raster3dThreadBox},
                          Case{"3dr", AntiAliasing::None, 1u}}) {
      const AntiAliasing aa = c.aa;
      SCOPED_TRACE(std::string(c.primary) + ", aa=" + toString(aa) + ", thread box " + std::to_string(c.threadBox));
      RenderSettings rs;
      rs.width = w;
      rs.height = h;
      rs.primary = hb::testing::primaryNamed(c.primary);
      rs.raster3dThreadBox = c.threadBox;
      rs.shading = ShadingMethod::Visbuffer;
      rs.lightCulling = false;
      rs.aa = aa;
      rs.effects.add(EffectSource::Config, "test", {{"shadows", false}});
      Renderer r(*ctx, scene, rs);
      const Raster3dPass& pass = *r.raster3d();
      ASSERT_EQ(pass.sharedPlanes(), aa != AntiAliasing::None);
      r.renderFrame(false);  // timed: the fast paths
      const std::span<const glm::vec2> samples = aaStoredPositions(aa);
      for (uint32_t p = 0; p < pass.planes(); ++p) {
        const Raster3dResult exact =
            p == 0
                ? exact0
                : rasterize3d(raster3dViewOf(raster3dConstants(cam, w, h, 0, 64, 64, samples[p - 1])), corners, order);
        const std::vector<uint64_t> vis = pass.readVisibility(p);
        size_t differ = 0;
        for (size_t i = 0; i < vis.size(); ++i) {
          differ += vis[i] != exact.visibility[i];
          hits += vis[i] != ~0ull;
        }
        EXPECT_EQ(differ, 0u) << "plane " << p << ": pixels whose (t, id) differs from the exact CPU rasterization";
      }
    }
  }
  EXPECT_GT(floatsWrong, 0u) << "the grids must hold pixels that the float edge values alone get wrong";
  EXPECT_GT(hits, size_t(3) * 8000u) << "the grids cover most of the view";
}

}  // namespace
}  // namespace hb::raster3d_test
