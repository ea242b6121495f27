// Anti-aliasing (aa = msaa4 | msaa8 | msaa16 | csaa-4-12; docs/methods/3d-rasterization.md
// "Anti-aliasing") on the real device:
//  - each stored sample's visibility plane is the exact 3D rasterization at that sample's position:
//    bit for bit the CPU reference's (ids and t) with its rays, and its coverage counted once per
//    sample where the exact rasterization counts one (0 holes, 0 double covers);
//  - a pixel a straight edge crosses resolves to the share of its samples on the lit side, in the
//    compute resolve (MSAA and CSAA) and in the raster pipeline's own multisampling;
//  - the refusals name what is wrong.
#include <cmath>
#include <cstdint>
#include <random>
#include <span>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "analysis/primary_analysis.h"
#include "analysis/render_outputs.h"
#include "app/scene_setup.h"
#include "base/errors.h"
#include "frame/passes/aa_samples.h"
#include "frame/passes/raster3d.h"
#include "frame/renderer.h"
#include "gpu_fixture.h"
#include "reference/raster3d_ref.h"
#include "triangle_scenes.h"

namespace hb {
namespace {

// A white diffuse surface: the shading error left after anti-aliasing is the lighting's alone.
Material whiteDiffuse() {
  Material m;
  m.metallicFactor = 0.0f;
  return m;
}

// Overlapping random triangles of many sizes and a shared-vertex heightfield grid under an oblique
// camera: ties, shared edges and vertices at every sample position.
Scene aaSoupAndGrid() {
  Scene s = testing::emptyScene("aa-soup-and-grid", testing::obliqueCamera(), whiteDiffuse());
  std::vector<glm::vec3> tris = testing::randomSoupCorners(s.cameras[0], 300, 7);
  const std::vector<glm::vec3> grid = testing::heightfieldCorners(24);
  tris.insert(tris.end(), grid.begin(), grid.end());
  testing::addTriangles(s, tris);
  return s;
}

RenderSettings aaSettings(const char* primary, const char* aa, uint32_t w, uint32_t h) {
  RenderSettings rs;
  rs.width = w;
  rs.height = h;
  rs.primary = hb::testing::primaryNamed(primary);
  rs.shading = rs.primary == PrimaryMethod::Hardware ? ShadingMethod::Forward : ShadingMethod::Visbuffer;
  static constexpr AntiAliasing kAll[] = {AntiAliasing::None, AntiAliasing::Msaa4, AntiAliasing::Msaa8,
                                          AntiAliasing::Msaa16, AntiAliasing::Csaa4x12};
  rs.aa = hb::testing::settingNamed(aa, kAll);
  rs.lightCulling = false;
  rs.effects.add(EffectSource::Config, "test", {{"shadows", false}});
  return rs;
}

using AaTest = hb::testing::GpuTest;

// The indices of a triangle soup's corners, in order (what the CPU rasterization takes).
std::vector<uint32_t> inOrder(size_t n) {
  std::vector<uint32_t> indices(n);
  for (size_t i = 0; i < n; ++i) indices[i] = uint32_t(i);
  return indices;
}

TEST_F(AaTest, EachSamplePlaneIsTheExactRasterizationAtItsSamplePosition) {
  const Scene scene = aaSoupAndGrid();
  const std::vector<glm::vec3> positions = scene.worldTriangles();
  const std::vector<uint32_t> indices = inOrder(positions.size());
  constexpr uint32_t w = 48, h = 36;
  // msaa16 holds every standard 16x position, msaa8 the 8x ones; the methods whose coverage is
  // additive (frustum culling drops only pairs that cover no sample of the frustum).
  for (const char* aa : {"msaa8", "msaa16"})
    for (const char* primary : {"3dr", "3dr-binned", "3dr-frustum-cull"}) {
      SCOPED_TRACE(std::string(primary) + ", aa=" + aa);
      Renderer r(*ctx, scene, aaSettings(primary, aa, w, h));
      r.renderFrame(true);
      const Raster3dPass& pass = *r.raster3d();
      const std::span<const glm::vec2> samples = aaStoredPositions(r.settings().aa);
      ASSERT_EQ(pass.planes(), 1 + samples.size());
      uint64_t covered = 0;
      const gpu::Raster3dConstants centre = raster3dConstants(scene.cameras[0], w, h, 0, 64, 64);
      for (uint32_t p = 1; p < pass.planes(); ++p) {
        const glm::vec2 s = samples[p - 1];
        const gpu::Raster3dConstants c = raster3dConstants(scene.cameras[0], w, h, 0, 64, 64, s);
        // The sample's rays are the centre's moved by (s − 0.5) pixels: d0 is rounded to float once in
        // each (half an ulp), the expected value is formed in double from those floats, so they agree
        // within an ulp of |d0| (2^-23 relative, taken twice). The screen boxes shift by the same
        // offset exactly (w/2 − s.x is exact in float for positions in sixteenths).
        const glm::dvec3 expect = glm::dvec3(centre.rayD0) + (double(s.x) - 0.5) * glm::dvec3(centre.rayDx) +
                                  (double(s.y) - 0.5) * glm::dvec3(centre.rayDy);
        const double ulp2 = std::ldexp(glm::length(glm::dvec3(centre.rayD0)), -22);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(double(c.rayD0[k]), expect[k], ulp2) << "sample " << p - 1;
        EXPECT_EQ(c.project.z, centre.project.z + 0.5f - s.x);
        EXPECT_EQ(c.project.w, centre.project.w + 0.5f - s.y);
        const Raster3dResult exact = rasterize3d(raster3dViewOf(c), positions, indices);
        const std::vector<uint64_t> vis = pass.readVisibility(p);
        const std::vector<uint32_t> count = pass.readCoverage(p);
        size_t differ = 0, holes = 0, doubles = 0;
        for (size_t i = 0; i < vis.size(); ++i) {
          differ += vis[i] != exact.visibility[i];
          holes += exact.coverage[i] > count[i];
          doubles += count[i] > exact.coverage[i];
          covered += count[i];
        }
        EXPECT_EQ(differ, 0u) << "sample " << p - 1 << ": pixels whose (t, id) differs from the CPU reference";
        EXPECT_EQ(holes, 0u) << "sample " << p - 1;
        EXPECT_EQ(doubles, 0u) << "sample " << p - 1;
      }
      EXPECT_GT(covered, uint64_t(w) * h) << "the scene covers the samples";
    }
}

// Timed frames of 3dr-binned rasterize the centre and every sample in one pass of setup, binning
// and tiles (shared sample planes, raster3d_common.glsl.inc); analysis frames go plane by plane, so
// the test above does not see that pass. Each plane of a timed frame must hold the exact CPU
// rasterization at its position, bit for bit (t and id, every tie and shared vertex).
TEST_F(AaTest, TimedFramesShareOnePassOverAllPlanesAndMatchTheExactRasterizationAtEachSample) {
  const Scene scene = aaSoupAndGrid();
  const std::vector<glm::vec3> positions = scene.worldTriangles();
  const std::vector<uint32_t> indices = inOrder(positions.size());
  constexpr uint32_t w = 48, h = 36;
  // A list of one entry a tile that never grows: triangles that find it full are rasterized by
  // their own thread at every plane (PASS 0 and the fill's fallbacks), the rest by the tile pass.
  for (const bool fullList : {false, true})
    for (const char* aa : {"msaa4", "msaa16"}) {
      SCOPED_TRACE(std::string("3dr-binned, aa=") + aa + (fullList ? ", a full list" : ""));
      RenderSettings rs = aaSettings("3dr-binned", aa, w, h);
      if (fullList) {
        rs.raster3dListPerTile = 1;
        rs.raster3dListGrows = false;
      }
      Renderer r(*ctx, scene, rs);
      const Raster3dPass& pass = *r.raster3d();
      ASSERT_TRUE(pass.sharedPlanes());
      r.renderFrame(false);
      if (fullList) {  // the analysis frame (plane by plane) counts what found the list full
        r.renderFrame(true);
        EXPECT_GT(pass.readCounters().listOverflows, 0u);
        r.renderFrame(false);
      }
      const std::span<const glm::vec2> samples = aaStoredPositions(r.settings().aa);
      size_t hits = 0;
      for (uint32_t p = 0; p < pass.planes(); ++p) {
        const gpu::Raster3dConstants c = p == 0 ? raster3dConstants(scene.cameras[0], w, h, 0, 64, 64)
                                                : raster3dConstants(scene.cameras[0], w, h, 0, 64, 64, samples[p - 1]);
        const Raster3dResult exact = rasterize3d(raster3dViewOf(c), positions, indices);
        const std::vector<uint64_t> vis = pass.readVisibility(p);
        size_t differ = 0;
        for (size_t i = 0; i < vis.size(); ++i) {
          differ += vis[i] != exact.visibility[i];
          hits += vis[i] != ~0ull;
        }
        EXPECT_EQ(differ, 0u) << "plane " << p << ": pixels whose (t, id) differs from the CPU reference";
      }
      EXPECT_GT(hits, size_t(w) * h) << "the scene covers the samples";
    }
}

// A white quad facing the eye whose right edge is vertical on the screen, `edge` of the way into
// pixel column `column`; directional light, no shadows, black sky beyond the edge.
Scene halfCoveredQuad(uint32_t w, uint32_t h, uint32_t column, double edge) {
  Camera cam;
  cam.view = glm::mat4(1.0f);  // eye at the origin looking down -z
  cam.yfov = 0.8f;
  cam.znear = 0.1f;
  cam.zfar = 100.0f;
  Scene s = testing::emptyScene("half-covered-quad", cam, whiteDiffuse());
  const double depth = 2.0, tanHalf = std::tan(0.4), a = double(w) / double(h);
  // Screen position u (pixels from the left edge) to view x at that depth: NDC 2u/W − 1.
  const double xEdge = (2.0 * (double(column) + edge) / double(w) - 1.0) * a * tanHalf * depth;
  const float x0 = -10.0f, x1 = float(xEdge), y0 = -10.0f, y1 = 10.0f, z = float(-depth);
  testing::addTriangles<glm::vec3>(s, {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y0, z}, {x1, y1, z}, {x0, y1, z}});
  Light l;
  l.type = LightType::Directional;
  l.direction = glm::normalize(glm::vec3(0.2f, -0.1f, -1.0f));
  l.intensity = 2.0f;
  l.castShadows = false;
  s.lights.push_back(l);
  return s;
}

TEST_F(AaTest, APixelAStraightEdgeCrossesResolvesToTheShareOfItsSamplesOnTheQuad) {
  constexpr uint32_t w = 32, h = 16, column = 20;
  // The edge 0.6 of the way into the column (the area covered): of the standard positions
  // (aa_samples.h) 2 of 4, 5 of 8, 10 of 16 and, for CSAA, 2 of its 4 stored and 7 of its 12
  // coverage samples lie left of it, so each mode resolves to its own share.
  constexpr double kEdge = 0.6;
  const Scene scene = halfCoveredQuad(w, h, column, kEdge);
  struct Case {
    const char *primary, *aa;
  };
  for (const Case c : {Case{"3dr", "msaa4"}, Case{"3dr-binned", "msaa8"}, Case{"3dr", "msaa16"},
                       Case{"3dr", "csaa-4-12"}, Case{"hardware", "msaa4"}}) {
    SCOPED_TRACE(std::string(c.primary) + ", aa=" + c.aa);
    Renderer r(*ctx, scene, aaSettings(c.primary, c.aa, w, h));
    r.renderFrame(false);
    const AntiAliasing aa = r.settings().aa;
    double left = 0;  // stored and coverage positions left of the edge
    const std::span<const glm::vec2> stored = aaStoredPositions(aa);
    for (const glm::vec2 s : stored) left += s.x < kEdge;
    double total = double(stored.size());
    if (aa == AntiAliasing::Csaa4x12)
      for (const glm::vec2 s : kCsaaCoverage) left += s.x < kEdge, total += 1;
    const double expected = left / total;
    const std::vector<float> color = r.readColor();
    auto at = [&](uint32_t x, uint32_t y, int ch) { return double(color[(size_t(y) * w + x) * 4 + size_t(ch)]); };
    for (uint32_t y = 2; y + 2 < h; ++y)
      for (int ch = 0; ch < 3; ++ch) {
        // The quad's shading at the edge pixel, from its two left neighbours (fully covered); the
        // shading changes by |C(x−1) − C(x−2)| a pixel (the view vector turns), so extrapolating
        // linearly errs by at most that; RGBA16F rounds each value to 2^-11 relative.
        const double c1 = at(column - 1, y, ch), c2 = at(column - 2, y, ch);
        ASSERT_GT(c1, 0.05) << "the quad is lit";
        const double shade = 2.0 * c1 - c2;
        const double tol = expected * std::fabs(c1 - c2) + 3.0 * std::ldexp(std::max(c1, shade), -11);
        EXPECT_NEAR(at(column, y, ch), expected * shade, tol) << "pixel (" << column << ", " << y << ")";
        EXPECT_EQ(at(column + 1, y, ch), 0.0) << "beyond the edge: the sky";
      }
  }
}

TEST_F(AaTest, WithoutAntiAliasingTheEdgePixelIsAllOrNothing) {
  constexpr uint32_t w = 32, h = 16, column = 20;
  const Scene scene = halfCoveredQuad(w, h, column, 0.6);
  Renderer r(*ctx, scene, aaSettings("3dr", "none", w, h));
  r.renderFrame(false);
  const std::vector<float> color = r.readColor();
  // The centre (0.5) lies left of the edge: the pixel is the quad's alone.
  const size_t edge = (size_t(8) * w + column) * 4, inside = (size_t(8) * w + column - 1) * 4;
  EXPECT_NEAR(color[edge], color[inside], 0.01 * color[inside]);
  EXPECT_EQ(color[edge + 4], 0.0f);
}

TEST_F(AaTest, RefusalsNameWhatIsWrong) {
  const Scene scene = halfCoveredQuad(32, 16, 20, 0.6);
  RenderSettings forward = aaSettings("3dr", "msaa4", 32, 16);
  forward.shading = ShadingMethod::Forward;
  try {
    Renderer r(*ctx, scene, forward);
    ADD_FAILURE() << "aa with the forward pass after 3dr was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("shading=visbuffer"), std::string::npos) << e.what();
  }
  try {
    Renderer r(*ctx, scene, aaSettings("hardware", "csaa-4-12", 32, 16));
    ADD_FAILURE() << "csaa on the raster pipeline was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("csaa-4-12"), std::string::npos) << e.what();
  }
}

// An AA variant's no-culling reference (the sweep's default, reference_ssaa 1) is rendered without
// AA, with the forward pass: it must be a frame the renderer accepts (it once kept the AA and was
// refused, failing every AA variant of a sweep without reference_ssaa).
TEST_F(AaTest, TheNoCullingReferenceOfAnAaVariantRenders) {
  const Scene scene = halfCoveredQuad(32, 16, 20, 0.6);
  VariantParams p;
  p.resolution = {32, 16};
  p.primary = PrimaryMethod::Raster3dBinned;
  p.shading = ShadingMethod::Visbuffer;
  p.aa = AntiAliasing::Msaa4;
  const VariantParams rp = referenceParams(p);
  EXPECT_EQ(rp.aa, AntiAliasing::None);
  Renderer r(*ctx, scene, renderSettingsFor(rp, EffectsRequest{}));
  r.renderFrame(true);
  EXPECT_GT(r.readColor()[(size_t(8) * 32 + 10) * 4], 0.0f) << "the quad is drawn";
}

}  // namespace
}  // namespace hb
