// The ray benchmark on the real device (lavapipe on CI): raybench re-traces exactly the shadow rays
// of the last analysis frame (shaders/shadows/raybench_common.glsl.inc). Its per-pixel count of
// unoccluded rays is held bit for bit against what the shadow pass itself recorded for the same
// rays, and a pixel whose stored ray origin is moved to another point traces that point's rays:
// its count becomes that point's, and no other pixel's count moves.
//
// What the shadow pass records (shaders/shadows/shadows_common.glsl.inc), per pixel, over the words
// of its light-list walk (word j of pixel i at j·pixels + i; bit b of word j = the (32j + b)-th light
// the walk visits):
//   visibility bit = the light reaches the point: an unoccluded shadow ray, or a light that casts no
//                    shadow (visible by definition, no ray);
//   traced bit     = a shadow ray was traced (analysis frames only).
// raybench walks the same list, skips every light whose traced bit is clear, and counts the rays it
// finds unoccluded, so its count must be popcount(visibility & traced) summed over the walk's words.
// The words past the walk's last are never written by either pass, and are not read here.
#include <algorithm>
#include <bit>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "effects/shadows/shadows_part.h"
#include "frame/renderer.h"
#include "gpu/descriptor_binder.h"
#include "gpu/sync.h"
#include "gpu/vk_pipeline.h"
#include "gpu/vk_resources.h"
#include "gpu_fixture.h"
#include "overwrite_positions_comp.h"  // generated from tests/shaders/overwrite_positions.comp.glsl (CMakeLists.txt)
#include "scene/atrium.h"
#include "shared/gpu_types.h"

namespace hb {
namespace {

// Small enough for lavapipe (at most 48 rays a pixel), large enough for 40 tiles of 16 x 16.
constexpr uint32_t kRayBenchWidth = 128, kRayBenchHeight = 72;
// Over 32 lights: the bitmask and z-bin walks take two words a pixel (the tile lists of the thesis
// are capped at 32, one word). Every third light casts no shadow, so that visibility bits without a
// traced bit exist and the AND with the traced words is needed (checked below).
constexpr uint32_t kRayBenchLights = 48;

const Scene& rayBenchAtrium() {
  static const Scene scene = [] {
    AtriumParams p;
    p.lightCount = kRayBenchLights;
    p.triangleScale = 0.25;
    Scene s = makeAtrium(p);
    for (size_t i = 0; i < s.lights.size(); i += 3) s.lights[i].castShadows = false;
    return s;
  }();
  return scene;
}

LightLists listsNamed(const std::string& name) {
  static constexpr LightLists kAll[] = {LightLists::Tile, LightLists::Bitmask, LightLists::Zbin};
  return hb::testing::settingNamed(name, kAll);
}

// An analysis frame of the atrium, then one raybench repetition on its rays. Normal culling and the
// range test are on so that the traced words differ from the walk (lights culled in the middle of
// a word), not only by the lights that cast no shadow.
struct RayBenchFrame {
  std::unique_ptr<Renderer> renderer;
  ShadowsPart* shadows = nullptr;
  ShadowReadback pass;           // the shadow pass's visibility, ranges, accounting, positions
  std::vector<uint32_t> traced;  // its traced words, word-major like the visibility
  std::vector<uint32_t> counts;  // raybench's per-pixel count
  size_t pixels() const { return size_t(kRayBenchWidth) * kRayBenchHeight; }
  // The words of pixel i's walk: ceil(k / 32) for a walk of k lights; an empty walk writes word 0.
  uint32_t walkWords(size_t i) const {
    const uint32_t k = pass.accounting[4 * i] >> gpu::kAccountBits;
    return k == 0 ? 1u : (k + 31) / 32;
  }
};

RayBenchFrame renderForRayBench(const VulkanContext& ctx, const std::string& backend, const std::string& lists) {
  RenderSettings s{.width = kRayBenchWidth,
                   .height = kRayBenchHeight,
                   .tileSize = 16,
                   .backend = hb::testing::backendNamed(backend),
                   .normals = NormalCulling::Improved};
  s.rangeTest = true;
  s.lightLists = listsNamed(lists);
  RayBenchFrame f;
  f.renderer = std::make_unique<Renderer>(ctx, rayBenchAtrium(), s);
  f.shadows = shadowsOf(*f.renderer);
  if (!f.shadows) {
    ADD_FAILURE() << "the atrium's frame has no shadows part";
    return f;
  }
  EXPECT_EQ(toString(f.shadows->shadowPass().settings().backend), backend);
  f.renderer->renderFrame(true);
  f.pass = f.shadows->readShadows();
  const std::vector<uint8_t> bytes = readbackBuffer(ctx, f.shadows->shadowPass().traced());
  f.traced.resize(bytes.size() / sizeof(uint32_t));
  std::memcpy(f.traced.data(), bytes.data(), f.traced.size() * sizeof(uint32_t));
  f.shadows->rayBench(f.renderer->timer(), 1);
  f.counts = f.shadows->readRayBench();
  return f;
}

// What raybench must count, from the shadow pass's own words, and how much of the frame that covers.
struct ExpectedCounts {
  std::vector<uint32_t> visible;  // per pixel popcount(visibility & traced) over its walk's words
  uint64_t visibleRays = 0, occludedRays = 0;
  uint64_t visibleUntraced = 0;  // visibility bits without a traced bit (lights that cast no shadow)
  size_t pixelsWithRays = 0, pixelsWithBoth = 0;
  size_t tracedCountMismatches = 0;  // pixels whose traced bits disagree with the accounting's count
};

ExpectedCounts expectedCounts(const RayBenchFrame& f) {
  ExpectedCounts e;
  const size_t pixels = f.pixels();
  e.visible.assign(pixels, 0);
  for (size_t i = 0; i < pixels; ++i) {
    uint32_t visible = 0, occluded = 0;
    for (uint32_t j = 0; j < f.walkWords(i); ++j) {
      const uint32_t v = f.pass.visibility[j * pixels + i], t = f.traced[j * pixels + i];
      visible += std::popcount(v & t);
      occluded += std::popcount(t & ~v);
      e.visibleUntraced += std::popcount(v & ~t);
    }
    e.visible[i] = visible;
    e.visibleRays += visible;
    e.occludedRays += occluded;
    e.pixelsWithRays += visible + occluded > 0;
    e.pixelsWithBoth += visible > 0 && occluded > 0;
    e.tracedCountMismatches += visible + occluded != (f.pass.accounting[4 * i] & gpu::kAccountMask);
  }
  return e;
}

using RayBenchCase = std::tuple<std::string, std::string>;  // backend, light lists

class RayBenchRays : public testing::GpuTest, public ::testing::WithParamInterface<RayBenchCase> {
 protected:
  std::string what() const { return std::get<0>(GetParam()) + " lists=" + std::get<1>(GetParam()); }
};

TEST_P(RayBenchRays, CountExactlyTheTracedRaysTheShadowPassFoundUnoccluded) {
  if (std::get<0>(GetParam()) == "rayquery") {
    HB_SKIP_WITHOUT_RAY_QUERY();
  }
  const RayBenchFrame f = renderForRayBench(*ctx, std::get<0>(GetParam()), std::get<1>(GetParam()));
  ASSERT_TRUE(f.shadows);
  ASSERT_EQ(f.counts.size(), f.pixels());
  const ExpectedCounts e = expectedCounts(f);
  // The traced words are read as the shaders write them: their bits add up to the accounting's
  // traced count in every pixel.
  EXPECT_EQ(e.tracedCountMismatches, 0u) << what();
  size_t mismatches = 0, first = f.pixels();
  for (size_t i = 0; i < f.pixels(); ++i)
    if (f.counts[i] != e.visible[i]) {
      ++mismatches;
      first = std::min(first, i);
    }
  EXPECT_EQ(mismatches, 0u) << what() << ": pixels where raybench's count differs from the shadow pass's; first "
                            << first << ": raybench " << (first < f.pixels() ? f.counts[first] : 0u) << ", shadow pass "
                            << (first < f.pixels() ? e.visible[first] : 0u);
  // The frame is a test of something: many pixels trace rays, some find the light and some do not,
  // and some lights are visible without a ray (popcount(visibility) alone would count them).
  EXPECT_GE(e.pixelsWithRays, f.pixels() / 4) << what();
  EXPECT_GT(e.pixelsWithBoth, 0u) << what();
  EXPECT_GT(e.visibleRays, 0u) << what();
  EXPECT_GT(e.occludedRays, 0u) << what();
  EXPECT_GT(e.visibleUntraced, 0u) << what();
  std::printf(
      "[ raybench ] %-28s %zu of %zu pixels trace rays (%zu with visible and occluded ones): %llu visible, %llu "
      "occluded rays, %llu lights visible without a ray; %zu pixels differ\n",
      what().c_str(), e.pixelsWithRays, f.pixels(), e.pixelsWithBoth, (unsigned long long)e.visibleRays,
      (unsigned long long)e.occludedRays, (unsigned long long)e.visibleUntraced, mismatches);
}

// Writes `points` (pixel x, y, then the new position) into the shadow pass's positions image, the
// ray origins raybench reads, through a compute pass of the test's own (the image is a storage image).
struct MovedPoint {
  uint32_t pixel[4];
  float position[4];
};
static_assert(sizeof(MovedPoint) == 32, "matches MovedPoint in tests/shaders/overwrite_positions.comp.glsl");

void overwritePositions(const VulkanContext& ctx, const Image& positions, const std::vector<MovedPoint>& points) {
  static const bool registered = (registerSpirv("overwrite_positions.comp", kSpirv_overwrite_positions_comp,
                                                sizeof kSpirv_overwrite_positions_comp),
                                  true);
  (void)registered;
  Buffer moves(ctx, points.size() * sizeof(MovedPoint), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, /*hostVisible=*/true);
  std::memcpy(moves.mapped(), points.data(), points.size() * sizeof(MovedPoint));
  DescriptorBinder binder("overwrite_positions");
  binder.provide("positions", positions, VK_IMAGE_LAYOUT_GENERAL);
  binder.provide("Moves", moves);
  Pipeline pipeline(ctx);
  pipeline.createCompute(binder, "overwrite_positions.comp", sizeof(uint32_t));
  binder.checkEveryNameRead();
  const uint32_t count = uint32_t(points.size());
  ctx.submitAndWait([&](VkCommandBuffer cmd) {
    Sync sync;
    sync.assume(positions, access::kAnyAccess);  // the frame that wrote and read it
    sync.use(cmd, {{positions, access::kComputeWrite}});
    VkDescriptorSet set = pipeline.set();
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.handle());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.layout(), 0, 1, &set, 0, nullptr);
    vkCmdPushConstants(cmd, pipeline.layout(), VK_SHADER_STAGE_ALL, 0, sizeof count, &count);
    vkCmdDispatch(cmd, (count + 63) / 64, 1, 1);
  });
}

// A pixel A takes the stored position of a pixel B of its own tile whose walk is the same (the same
// tile list; z-bin: the same bin range) and whose traced words are the same: A's rays are then B's
// rays bit for bit (origin, t_min = f(origin), direction and t_max from the same floats, the same
// lights), so A's new count must be B's count, exactly. B is chosen with a count other than A's, so
// the count must change; every other pixel traces what it traced before and keeps its count.
TEST_P(RayBenchRays, FollowAPixelsMovedRayOriginAndNoOtherPixelChanges) {
  if (std::get<0>(GetParam()) == "rayquery") {
    HB_SKIP_WITHOUT_RAY_QUERY();
  }
  RayBenchFrame f = renderForRayBench(*ctx, std::get<0>(GetParam()), std::get<1>(GetParam()));
  ASSERT_TRUE(f.shadows);
  const size_t pixels = f.pixels();
  const uint32_t tile = 16, tilesX = (kRayBenchWidth + tile - 1) / tile, tilesY = (kRayBenchHeight + tile - 1) / tile;
  auto sameRays = [&](size_t a, size_t b) {
    if (f.pass.positions[4 * a + 3] != 1.0f || f.pass.positions[4 * b + 3] != 1.0f) return false;  // sky
    if (!f.pass.ranges.empty() && f.pass.ranges[a] != f.pass.ranges[b]) return false;
    if (f.pass.accounting[4 * a] != f.pass.accounting[4 * b]) return false;  // walk length, traced count
    for (uint32_t j = 0; j < f.walkWords(a); ++j)
      if (f.traced[j * pixels + a] != f.traced[j * pixels + b]) return false;
    return true;
  };
  // Up to kPerTile moved pixels a tile, each with the first donor of its tile that qualifies.
  constexpr size_t kPerTile = 4;
  std::vector<MovedPoint> moves;
  std::vector<std::pair<size_t, size_t>> pairs;  // (moved pixel, donor)
  for (uint32_t ty = 0; ty < tilesY; ++ty)
    for (uint32_t tx = 0; tx < tilesX; ++tx) {
      std::vector<size_t> inTile;
      for (uint32_t y = ty * tile; y < std::min((ty + 1) * tile, kRayBenchHeight); ++y)
        for (uint32_t x = tx * tile; x < std::min((tx + 1) * tile, kRayBenchWidth); ++x)
          inTile.push_back(size_t(y) * kRayBenchWidth + x);
      size_t taken = 0;
      for (size_t a : inTile) {
        if (taken == kPerTile) break;
        for (size_t b : inTile)
          if (f.counts[b] != f.counts[a] && sameRays(a, b)) {
            MovedPoint m{{uint32_t(a % kRayBenchWidth), uint32_t(a / kRayBenchWidth), 0, 0}, {}};
            std::copy_n(&f.pass.positions[4 * b], 4, m.position);
            moves.push_back(m);
            pairs.emplace_back(a, b);
            ++taken;
            break;
          }
      }
    }
  ASSERT_GE(pairs.size(), 8u) << what() << ": too few pixels with a same-walk neighbour of another count";

  overwritePositions(*ctx, f.shadows->shadowPass().positions(), moves);
  // The positions image now holds the donors' points at the moved pixels, and nothing else moved.
  const std::vector<uint8_t> bytes =
      readbackImage(*ctx, f.shadows->shadowPass().positions(), VK_IMAGE_LAYOUT_GENERAL, 16);
  std::vector<float> moved(bytes.size() / sizeof(float));
  std::memcpy(moved.data(), bytes.data(), bytes.size());
  std::vector<float> expectedPositions = f.pass.positions;
  for (auto [a, b] : pairs) std::copy_n(&f.pass.positions[4 * b], 4, &expectedPositions[4 * a]);
  ASSERT_EQ(moved, expectedPositions) << what() << ": the positions image was not overwritten as asked";

  f.shadows->rayBench(f.renderer->timer(), 1);
  const std::vector<uint32_t> after = f.shadows->readRayBench();
  ASSERT_EQ(after.size(), pixels);
  std::vector<bool> isMoved(pixels, false);
  size_t movedWrong = 0, changed = 0;
  for (auto [a, b] : pairs) {
    isMoved[a] = true;
    movedWrong += after[a] != f.counts[b];
    changed += after[a] != f.counts[a];
  }
  size_t othersChanged = 0;
  for (size_t i = 0; i < pixels; ++i) othersChanged += !isMoved[i] && after[i] != f.counts[i];
  EXPECT_EQ(movedWrong, 0u) << what() << ": moved pixels whose count is not their donor's";
  EXPECT_EQ(changed, pairs.size()) << what() << ": moved pixels whose count did not change";
  EXPECT_EQ(othersChanged, 0u) << what() << ": pixels not moved whose count changed";
  std::printf(
      "[ raybench ] %-28s moved %zu ray origins: %zu counts changed, %zu equal their donor's; %zu others changed\n",
      what().c_str(), pairs.size(), changed, pairs.size() - movedWrong, othersChanged);
}

INSTANTIATE_TEST_SUITE_P(BackendsAndLists, RayBenchRays,
                         ::testing::Combine(::testing::Values("rayquery", "pipeline"),
                                            ::testing::Values("tile", "bitmask", "zbin")),
                         [](const ::testing::TestParamInfo<RayBenchCase>& param) {
                           return std::get<0>(param.param) + "_" + std::get<1>(param.param);
                         });

}  // namespace
}  // namespace hb
