// Many lights without dropping a ray (issue #17), on the real device (lavapipe on CI): the uncapped
// light lists (bitmask, zbin) with 33, 64, 100 and 256 lights in the atrium. Every (pixel, light)
// pair of a pixel's list is repeated by a double-precision CPU shadow ray from the GPU's own
// position and normal; no light that reaches a pixel is missing from its list (the exact culling
// reference, and z-binning's own per-pixel check); nothing is dropped; the accounting adds up; and
// the analysis on every core equals the serial one bit for bit.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "analysis/culling_analysis.h"
#include "analysis/ray_analysis.h"
#include "base/errors.h"
#include "base/parallel.h"
#include "effects/shadows/shadows_part.h"
#include "frame/renderer.h"
#include "gpu/gpu_lights.h"
#include "gpu_fixture.h"
#include "reference/bvh.h"
#include "scene/atrium.h"
#include "shadow_frame.h"
#include "shared/gpu_types.h"

namespace hb {
namespace {

// Small images keep lavapipe's rays (up to 256 a pixel) within seconds.
constexpr uint32_t kWidth = 96, kHeight = 54;

using ManyLightsFrame = hb::testing::ShadowedFrame;

ManyLightsFrame render(const VulkanContext& ctx, const Scene& scene, LightLists lists,
                       NormalCulling normals = NormalCulling::Improved, const std::string& primary = "hardware") {
  RenderSettings s{.width = kWidth, .height = kHeight, .tileSize = 16};
  s.lightLists = lists;
  s.rangeTest = true;
  s.normals = normals;
  s.primary = hb::testing::primaryNamed(primary);
  Renderer r(ctx, scene, s);
  r.renderFrame(true);
  return {s, r.readDepth(), r.readCulling(), shadowsOf(r)->readShadows(), r.view(), r.proj()};
}

const Scene& atrium(uint32_t lights) {
  static std::map<uint32_t, Scene> cache;
  auto it = cache.find(lights);
  if (it == cache.end()) {
    AtriumParams p;
    p.lightCount = lights;
    p.triangleScale = 0.25;
    it = cache.emplace(lights, makeAtrium(p)).first;
  }
  return it->second;
}

CullingInputs cullingInputs(const ManyLightsFrame& f, const Scene& scene) {
  CullingInputs ci;
  ci.depth = &f.depth;
  ci.lights = &scene.lights;
  ci.view = f.view;
  ci.proj = f.proj;
  ci.width = f.settings.width;
  ci.height = f.settings.height;
  ci.tileSize = f.settings.tileSize;
  ci.capacity = f.culling.capacity;
  return ci;
}

// The scene lights a pixel sees lit, as a sorted list (its walk's visibility bits mapped back).
std::vector<uint32_t> litLights(const ManyLightsFrame& f, size_t pixel) {
  const size_t pixels = f.depth.size();
  const uint32_t x = uint32_t(pixel % f.settings.width), y = uint32_t(pixel / f.settings.width);
  const uint32_t tile = (y / f.settings.tileSize) * f.culling.tilesX + x / f.settings.tileSize;
  const auto [first, last] =
      f.culling.pixelSlice(tile, f.culling.lists == LightLists::Zbin ? f.shadows.ranges[pixel] : 0u);
  std::vector<uint32_t> lit;
  for (uint32_t k = 0; k < last - first; ++k)
    if ((f.shadows.visibility[size_t(k / 32) * pixels + pixel] >> (k % 32)) & 1u)
      lit.push_back(f.culling.indices[first + k]);
  std::sort(lit.begin(), lit.end());
  return lit;
}

class ManyLightsGpuTest : public testing::GpuTest, public ::testing::WithParamInterface<uint32_t> {};

TEST_P(ManyLightsGpuTest, UncappedListsDropNothingAndMatchTheCpuShadowRays) {
  const uint32_t lightCount = GetParam();
  const Scene& scene = atrium(lightCount);
  const Bvh bvh = buildBvh(scene);
  const auto rcam = [&](const ManyLightsFrame& f) {
    return reconstructionCamera<double>(glm::dmat4(f.view), glm::dmat4(f.proj), f.settings.width, f.settings.height);
  };
  std::map<LightLists, ManyLightsFrame> frames;
  for (LightLists lists : {LightLists::Tile, LightLists::Bitmask, LightLists::Zbin}) {
    SCOPED_TRACE(toString(lists));
    const ManyLightsFrame f = render(*ctx, scene, lists);
    const RayAccounting acc = accountRays(f.shadows, f.culling, f.depth, kWidth, kHeight, 16, lightCount);
    EXPECT_TRUE(acc.addsUp());
    EXPECT_EQ(acc.walkMismatches, 0u);
    if (lists == LightLists::Tile) {
      // The thesis's lists overflow past 32: the dropped pairs are counted, not hidden.
      const bool overflow =
          std::any_of(f.culling.total.begin(), f.culling.total.end(), [](uint32_t t) { return t > 32; });
      EXPECT_EQ(acc.droppedByOverflow > 0, overflow);
      if (lightCount >= 100) {
        EXPECT_TRUE(overflow);
      }
      frames.emplace(lists, f);
      continue;
    }
    EXPECT_EQ(acc.droppedByOverflow, 0u);
    EXPECT_EQ(f.shadows.words, (lightCount + 31) / 32);
    // Every pair of every pixel's list, traced again in double from the GPU's position and normal:
    // a disagreement must be one float rounding can decide (ray_analysis.h compareShadows).
    const ShadowComparison cmp = compareShadows(scene, bvh, f.shadows, f.culling, kWidth, kHeight, 16, true);
    EXPECT_GT(cmp.rays, 0u);
    EXPECT_EQ(cmp.pairs, acc.candidates - acc.culledByTile - acc.culledByZbin);
    EXPECT_EQ(cmp.unexplained(), 0u) << cmp.mismatches << " mismatches of " << cmp.pairs << " pairs";
    EXPECT_LE(cmp.mismatches, cmp.pairs / 1000 + 2);
    // No light that reaches a pixel is missing from the lists: the exact (double) tile test ...
    const CullingInputs ci = cullingInputs(f, scene);
    const CullingAnalysis ca = analyzeCulling(ci, f.culling);
    EXPECT_EQ(ca.stats.falseNegatives, 0u);
    EXPECT_EQ(ca.stats.droppedByOverflow, 0u);
    EXPECT_EQ(ca.stats.overflowTiles, 0u);
    EXPECT_EQ(ca.comparison.hardMismatches, 0u);
    EXPECT_EQ(ca.comparison.malformedTiles, 0u);
    // ... and per pixel, z-binning's ranges keep every light that reaches the pixel's point.
    if (lists == LightLists::Zbin) {
      EXPECT_EQ(zbinMissedPairs(ci, f.culling, f.shadows.ranges), 0u);
      EXPECT_GT(acc.culledByZbin, 0u);  // the bins do cut lists
    }
    // With the range test and exact normals nothing can cull wrongly, so no variant traces fewer
    // rays than the oracle needs: the triangle's own normal (3D rasterization's ids) decides N·L as
    // the oracle does, up to float ties; without normal culling every ray in range is traced.
    for (const auto& [normals, primary] :
         {std::pair{NormalCulling::Geometric, "3dr"}, std::pair{NormalCulling::Off, "hardware"}}) {
      SCOPED_TRACE(primary);
      const ManyLightsFrame e = render(*ctx, scene, lists, normals, primary);
      const RayAccounting ea = accountRays(e.shadows, e.culling, e.depth, kWidth, kHeight, 16, lightCount);
      EXPECT_TRUE(ea.addsUp());
      const OracleRays oracle = oracleRays(scene, referenceSurface(bvh, e.depth, rcam(e)));
      EXPECT_GT(oracle.total, 0u);
      EXPECT_LE(rayEfficiency(oracle.total, ea.traced), 1.0) << oracle.total << " oracle, " << ea.traced << " traced";
    }
    frames.emplace(lists, f);
  }
  // bitmask and zbin see the same lit lights at every pixel and trace the same rays: a light outside
  // a pixel's bin range is outside its range ball, which the range test removes anyway.
  const ManyLightsFrame& b = frames.at(LightLists::Bitmask);
  const ManyLightsFrame& z = frames.at(LightLists::Zbin);
  size_t differing = 0;
  for (size_t i = 0; i < b.depth.size(); ++i)
    if (b.depth[i] > 0.0f) differing += litLights(b, i) != litLights(z, i);
  EXPECT_EQ(differing, 0u);
  const RayAccounting ab = accountRays(b.shadows, b.culling, b.depth, kWidth, kHeight, 16, lightCount);
  const RayAccounting az = accountRays(z.shadows, z.culling, z.depth, kWidth, kHeight, 16, lightCount);
  EXPECT_EQ(ab.traced, az.traced);
  EXPECT_EQ(ab.culledByTile + ab.culledByRange, az.culledByTile + az.culledByZbin + az.culledByRange);
}

INSTANTIATE_TEST_SUITE_P(Lights, ManyLightsGpuTest, ::testing::Values(33u, 64u, 100u, 256u),
                         [](const auto& param) { return std::to_string(param.param); });

// Without a shadow pass the shading pass takes each pixel's z-bin range from its own depth: it
// must light every pixel with the same lights as the bitmask lists do. The colours differ only by
// the order the same terms are summed in (a few float ulps), below one step of the RGBA16F target
// (2^-10 relative near the value): per channel |zbin - bitmask| <= 2^-10 · max(|zbin|, |bitmask|)
// plus 2^-24 for values near zero (half's subnormal step).
class ManyLightsShadingTest : public testing::GpuTest {};

TEST_F(ManyLightsShadingTest, ZbinShadingWithoutShadowsLightsLikeTheBitmaskLists) {
  const Scene& scene = atrium(64);
  std::map<LightLists, std::vector<float>> colors;
  for (LightLists lists : {LightLists::Bitmask, LightLists::Zbin}) {
    RenderSettings s{.width = kWidth, .height = kHeight, .tileSize = 16};
    s.lightLists = lists;
    s.effects.add(EffectSource::Config, "test", {{"shadows", false}});
    Renderer r(*ctx, scene, s);
    ASSERT_FALSE((shadowsOf(r) != nullptr));
    r.renderFrame(true);
    colors[lists] = r.readColor();
  }
  const std::vector<float>& b = colors.at(LightLists::Bitmask);
  const std::vector<float>& z = colors.at(LightLists::Zbin);
  ASSERT_EQ(b.size(), z.size());
  size_t off = 0, lit = 0;
  for (size_t i = 0; i < b.size(); ++i) {
    lit += b[i] > 0.0f;
    off += std::abs(b[i] - z[i]) > std::ldexp(std::max(std::abs(b[i]), std::abs(z[i])), -10) + 0x1p-24f;
  }
  EXPECT_GT(lit, b.size() / 4);
  EXPECT_EQ(off, 0u);
}

// The analysis on every core (parallelFor) equals the serial run (HYBRIDBENCH_THREADS=1) bit for bit.
class ManyLightsAnalysisTest : public testing::GpuTest {};

TEST_F(ManyLightsAnalysisTest, MultithreadedAnalysisEqualsTheSerialOneBitForBit) {
  const Scene& scene = atrium(100);
  const ManyLightsFrame f = render(*ctx, scene, LightLists::Zbin);
  const Bvh bvh = buildBvh(scene);
  const auto cam = reconstructionCamera<double>(glm::dmat4(f.view), glm::dmat4(f.proj), kWidth, kHeight);
  struct Result {
    RayAccounting acc;
    ReferenceSurface surface;
    OracleRays oracle;
    ShadowComparison cmp;
    CullingReference ref;
    uint64_t zbinMissed;
  };
  auto analyse = [&](const char* threads) {
    setenv("HYBRIDBENCH_THREADS", threads, 1);
    Result r;
    r.acc = accountRays(f.shadows, f.culling, f.depth, kWidth, kHeight, 16, 100);
    r.surface = referenceSurface(bvh, f.depth, cam);
    r.oracle = oracleRays(scene, r.surface);
    r.cmp = compareShadows(scene, bvh, f.shadows, f.culling, kWidth, kHeight, 16, true);
    const CullingInputs ci = cullingInputs(f, scene);
    r.ref = cullingReference(ci);
    r.zbinMissed = zbinMissedPairs(ci, f.culling, f.shadows.ranges);
    unsetenv("HYBRIDBENCH_THREADS");
    return r;
  };
  const Result serial = analyse("1"), parallel = analyse("7");
  EXPECT_EQ(toJson(serial.acc), toJson(parallel.acc));
  EXPECT_EQ(serial.acc.perPixel, parallel.acc.perPixel);
  EXPECT_EQ(serial.surface.position, parallel.surface.position);
  EXPECT_EQ(serial.surface.normal, parallel.surface.normal);
  EXPECT_EQ(serial.surface.matched, parallel.surface.matched);
  EXPECT_EQ(serial.oracle.perPixel, parallel.oracle.perPixel);
  EXPECT_EQ(serial.oracle.total, parallel.oracle.total);
  EXPECT_EQ(serial.cmp.visibility, parallel.cmp.visibility);
  EXPECT_EQ(serial.cmp.mismatches, parallel.cmp.mismatches);
  EXPECT_EQ(serial.cmp.rays, parallel.cmp.rays);
  EXPECT_EQ(serial.ref.exact, parallel.ref.exact);
  EXPECT_EQ(serial.ref.needed, parallel.ref.needed);
  EXPECT_EQ(serial.ref.sameAll, parallel.ref.sameAll);
  EXPECT_EQ(serial.zbinMissed, parallel.zbinMissed);
}

TEST(AnalysisThreads, ABadThreadCountIsAnInputError) {
  setenv("HYBRIDBENCH_THREADS", "zero", 1);
  EXPECT_THROW(analysisThreads(), InputError);
  setenv("HYBRIDBENCH_THREADS", "3", 1);
  EXPECT_EQ(analysisThreads(), 3u);
  unsetenv("HYBRIDBENCH_THREADS");
}

}  // namespace
}  // namespace hb
