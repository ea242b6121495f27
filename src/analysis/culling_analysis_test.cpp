// CPU-only tests of culling_analysis: the reference, the statistics, the heatmap, the JSON and the
// GPU-vs-reference comparison, with the "GPU" readback built on the CPU (the real GPU is tested
// in tests/light_culling_gpu_test.cpp).
#include "analysis/culling_analysis.h"

#include <algorithm>
#include <random>

#include <gtest/gtest.h>

#include "frame/renderer.h"
#include "scene/camera.h"

namespace hb {
namespace {

// 64x48 image, 16 px tiles (4x3 tiles). Left half: a slanted surface at view distance 4..5.6;
// right half: sky. A rigid, non-identity view so that the lights go through the transform.
struct SyntheticView {
  uint32_t width = 64, height = 48;
  glm::mat4 view = lookAt({1.0f, 2.0f, 3.0f}, {1.5f, 2.0f, -2.0f}, {0.0f, 1.0f, 0.0f});
  glm::mat4 proj = reverseZProjection(64.0f / 48.0f, 1.0f, 0.1f, 100.0f);
  std::vector<float> depth;
  std::vector<Light> lights;

  SyntheticView() {
    depth.assign(size_t(width) * height, 0.0f);
    for (uint32_t y = 0; y < height; ++y)
      for (uint32_t x = 0; x < width / 2; ++x) {
        const float dist = 4.0f + 0.05f * float(x);
        depth[size_t(y) * width + x] = proj[3][2] / dist - proj[2][2];  // inverse of viewZFromDepth
      }
  }
  // A world-space point from a view-space one.
  glm::vec3 world(glm::dvec3 viewPos) const {
    return glm::vec3(glm::inverse(glm::dmat4(view)) * glm::dvec4(viewPos, 1.0));
  }
  CullingInputs inputs(uint32_t capacity = kDefaultTileCapacity, bool aabb = false, bool culling = true) const {
    CullingInputs in;
    in.depth = &depth;
    in.lights = &lights;
    in.view = view;
    in.proj = proj;
    in.width = width;
    in.height = height;
    in.tileSize = 16;
    in.capacity = capacity;
    in.aabb = aabb;
    in.lightCulling = culling;
    return in;
  }
};

Light pointAt(glm::vec3 p, float range) { return Light{.position = p, .range = range}; }

void addRandomLights(SyntheticView& s, uint32_t count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (uint32_t i = 0; i < count; ++i) {
    const glm::dvec3 v(3.0 * u(rng), 2.5 * u(rng), -5.0 + 3.0 * u(rng));
    Light l = pointAt(s.world(v), float(0.3 + 1.5 * (u(rng) + 1.0)));
    if (i % 3 == 1) {
      l.type = LightType::Spot;
      l.direction = glm::normalize(glm::vec3(float(u(rng)), float(u(rng)), float(u(rng))));
      l.outerConeAngle = float(0.8 * (u(rng) + 1.0));  // up to 1.6 rad: some beyond 89 degrees
    }
    s.lights.push_back(l);
  }
}

// The readback a correct GPU would produce: the reference's stored lists at stride capacity.
CullingReadback fakeReadback(const CullingInputs& in, const CullingReference& ref, bool reverseOrder = false) {
  CullingReadback r;
  r.tilesX = tileCount(in.width, in.tileSize);
  r.tilesY = tileCount(in.height, in.tileSize);
  r.capacity = in.capacity;
  r.indices.assign(ref.same.size() * in.capacity, 0xdeadbeefu);
  for (size_t t = 0; t < ref.same.size(); ++t) {
    auto list = ref.same[t].indices;
    if (reverseOrder) std::reverse(list.begin(), list.end());
    r.offset.push_back(uint32_t(t * in.capacity));
    r.count.push_back(uint32_t(list.size()));
    r.total.push_back(ref.same[t].total);
    std::copy(list.begin(), list.end(), r.indices.begin() + t * in.capacity);
  }
  return r;
}

TEST(CullingAnalysis, SameMethodReferenceKeepsEveryExactLightAndSkyTilesGetNone) {
  SyntheticView s;
  addRandomLights(s, 40, 5);
  for (bool aabb : {false, true}) {
    const CullingInputs in = s.inputs(64, aabb);
    const CullingReference ref = cullingReference(in);
    ASSERT_EQ(ref.same.size(), 12u);
    uint64_t exactPairs = 0;
    for (size_t t = 0; t < ref.same.size(); ++t) {
      for (uint32_t i : ref.exact[t]) EXPECT_TRUE(std::binary_search(ref.sameAll[t].begin(), ref.sameAll[t].end(), i));
      exactPairs += ref.exact[t].size();
      if (t % 4 >= 2) {  // right half: sky
        EXPECT_TRUE(ref.exact[t].empty());
        EXPECT_EQ(ref.same[t].total, 0u);
      }
    }
    EXPECT_GT(exactPairs, 20u);  // the scene must exercise the test
  }
}

TEST(CullingAnalysis, ListsEqualToTheReferenceCompareCleanInAnyOrder) {
  SyntheticView s;
  addRandomLights(s, 40, 6);
  const CullingInputs in = s.inputs();
  const CullingReference ref = cullingReference(in);
  const CullingComparison c = compareGpuToReference(in, fakeReadback(in, ref, true), ref);
  EXPECT_TRUE(c.ok());
  EXPECT_EQ(c.hardMismatches + c.borderlineMismatches, 0u);
}

TEST(CullingAnalysis, AFarLightInAGpuListIsAHardMismatch) {
  SyntheticView s;
  addRandomLights(s, 10, 7);
  s.lights.push_back(pointAt(s.world({0.0, 0.0, 50.0}), 0.1f));  // behind the camera, tiny
  const CullingInputs in = s.inputs();
  const CullingReference ref = cullingReference(in);
  CullingReadback gpu = fakeReadback(in, ref);
  ASSERT_LT(gpu.count[0], in.capacity);
  gpu.indices[gpu.count[0]] = 10;
  ++gpu.count[0];
  ++gpu.total[0];
  const CullingComparison c = compareGpuToReference(in, gpu, ref);
  EXPECT_EQ(c.hardMismatches, 1u);
  ASSERT_EQ(c.mismatches.size(), 1u);
  EXPECT_EQ(c.mismatches[0].tile, 0u);
  EXPECT_EQ(c.mismatches[0].light, 10u);
  EXPECT_TRUE(c.mismatches[0].gpuKept);
  EXPECT_FALSE(c.ok());
}

TEST(CullingAnalysis, ATangentLightFlippedByRoundingIsBorderline) {
  SyntheticView s;
  const CullingInputs in0 = s.inputs();
  // Tile (1, 1): a sphere just touching its left plane from outside. Its centre lies 2 units
  // outside; the radius overshoots by 1e-9 relative, far below float rounding (6e-8).
  const auto proj = projectionParams(glm::dmat4(s.proj));
  const TileRect rect = tileRect(1, 1, 16, s.width, s.height);
  const auto range = tileDepthRange(s.depth, s.width, s.height, rect);
  const auto vol = tileVolume(proj, rect, s.width, s.height, double(range.minDepth), double(range.maxDepth));
  const glm::dvec3 mid = (vol.corners[0] + vol.corners[2] + vol.corners[4] + vol.corners[6]) / 4.0;
  const glm::dvec3 centre = mid - 2.0 * vol.planes[0].n;
  s.lights.push_back(pointAt(s.world(centre), 2.0f));
  // The light went through float: measure its actual margin and make it tangent again.
  ViewLight<double> vl = toViewLight(s.lights[0], glm::dmat4(s.view));
  const double outside = -(glm::dot(vol.planes[0].n, vl.position) + vol.planes[0].d);
  s.lights[0].range = float(outside);
  vl = toViewLight(s.lights[0], glm::dmat4(s.view));
  const double margin = cullingDecisionMargin(vol, vl, false);
  const double bound =
      cullingRoundingBound(tileCornerRays(proj, rect, s.width, s.height), vol, vl,
                           glm::length(glm::dvec3(s.lights[0].position)), glm::length(glm::dvec3(s.view[3])));
  ASSERT_LE(margin, bound);
  const CullingReference ref = cullingReference(in0);
  // Flip the decision in the "GPU" list of tile (1, 1) = tile 5.
  CullingReadback gpu = fakeReadback(in0, ref);
  const bool kept = ref.same[5].total == 1;
  gpu.count[5] = gpu.total[5] = kept ? 0 : 1;
  gpu.indices[5 * in0.capacity] = 0;
  const CullingComparison c = compareGpuToReference(in0, gpu, ref);
  EXPECT_EQ(c.hardMismatches, 0u);
  EXPECT_EQ(c.borderlineMismatches, 1u);
  EXPECT_TRUE(c.ok());
  ASSERT_EQ(c.mismatches.size(), 1u);
  EXPECT_EQ(c.mismatches[0].gpuKept, !kept);
}

TEST(CullingAnalysis, OverflowingTileIsComparedUpToItsLastStoredIndex) {
  SyntheticView s;
  // 10 lights that all reach tile 0 (a sphere round the camera), capacity 4.
  for (int i = 0; i < 10; ++i) s.lights.push_back(pointAt(s.world({0.1 * i, 0.0, 0.0}), 20.0f));
  const CullingInputs in = s.inputs(4);
  const CullingReference ref = cullingReference(in);
  ASSERT_EQ(ref.same[0].total, 10u);
  EXPECT_EQ(ref.same[0].indices, (std::vector<uint32_t>{0, 1, 2, 3}));
  CullingReadback gpu = fakeReadback(in, ref);
  EXPECT_TRUE(compareGpuToReference(in, gpu, ref).ok());
  // Storing {0, 1, 2, 4} instead: 4 is kept by the reference too (not stored there, but no
  // mismatch); 3 was kept and is missing below the last stored index 4: a hard mismatch.
  gpu.indices[3] = 4;
  const CullingComparison c = compareGpuToReference(in, gpu, ref);
  EXPECT_EQ(c.hardMismatches, 1u);
  ASSERT_EQ(c.mismatches.size(), 1u);
  EXPECT_EQ(c.mismatches[0].light, 3u);
  EXPECT_FALSE(c.mismatches[0].gpuKept);
  // The statistics count the overflow and what it dropped.
  const CullStatistics st = gpuCullStatistics(in, fakeReadback(in, ref), ref);
  EXPECT_GT(st.overflowTiles, 0u);
  EXPECT_GT(st.droppedByOverflow, 0u);
  EXPECT_EQ(st.falseNegatives, 0u);
}

TEST(CullingAnalysis, InconsistentGridEntriesAreReported) {
  SyntheticView s;
  addRandomLights(s, 10, 8);
  const CullingInputs in = s.inputs();
  const CullingReference ref = cullingReference(in);
  CullingReadback gpu = fakeReadback(in, ref);
  gpu.total[0] = gpu.count[0] + 1;  // claims overflow below capacity
  gpu.offset[1] = 0;                // slice of another tile
  const CullingComparison c = compareGpuToReference(in, gpu, ref);
  EXPECT_EQ(c.malformedTiles, 2u);
  EXPECT_FALSE(c.ok());
}

TEST(CullingAnalysis, TotalsThatDifferBeyondTheBorderlineLightsAreReported) {
  SyntheticView s;
  // 10 lights whose spheres hold the whole view (no decision anywhere near a threshold).
  for (int i = 0; i < 10; ++i) s.lights.push_back(pointAt(s.world({0.1 * i, 0.0, 0.0}), 20.0f));
  const CullingInputs in = s.inputs(4);
  const CullingReference ref = cullingReference(in);
  CullingReadback gpu = fakeReadback(in, ref);
  ASSERT_EQ(gpu.total[0], 10u);
  gpu.total[0] = 13;  // three more lights than there are; the stored list is still well-formed
  const CullingComparison c = compareGpuToReference(in, gpu, ref);
  EXPECT_EQ(c.totalMismatchTiles, 1u);
  EXPECT_EQ(c.malformedTiles, 0u);
  EXPECT_FALSE(c.ok());
}

TEST(CullingAnalysis, CullingOffListsEveryLightAndCountsSkyAsFalsePositives) {
  SyntheticView s;
  addRandomLights(s, 6, 10);
  const CullingInputs in = s.inputs(kDefaultTileCapacity, false, false);
  const CullingAnalysis a = analyzeCulling(in, fakeReadback(in, cullingReference(in)));
  for (const auto& l : a.reference.same) EXPECT_EQ(l.total, 6u);
  EXPECT_EQ(a.stats.meanLightsPerTile, 6.0);
  EXPECT_EQ(a.stats.falseNegatives, 0u);
  // Half the tiles are sky (no exact light), so at least half the stored pairs are false.
  EXPECT_GE(a.stats.falsePositiveRate, 0.5);
  EXPECT_TRUE(a.comparison.ok());
  EXPECT_EQ(a.json["light_culling"], false);
}

TEST(CullingAnalysis, HeatmapColoursEveryPixelByItsTilesTotal) {
  SyntheticView s;
  s.width = 40;  // not a multiple of 16: partial tiles (3 x 3)
  s.height = 40;
  s.depth.assign(40 * 40, 0.5f);
  addRandomLights(s, 12, 11);
  const CullingInputs in = s.inputs();
  CullingReadback gpu = fakeReadback(in, cullingReference(in));
  for (size_t t = 0; t < gpu.total.size(); ++t) gpu.total[t] = uint32_t(t);  // only the image reads it
  const ImageRGBA8 img = lightsPerTileHeatmap(in, gpu);
  ASSERT_EQ(img.width, 40u);
  ASSERT_EQ(img.px.size(), 40u * 40u * 4u);
  for (uint32_t y : {0u, 15u, 16u, 39u})
    for (uint32_t x : {0u, 17u, 33u, 39u}) {
      const Rgb8 want = thesisHeatColor(double((y / 16) * 3 + x / 16) / 12.0);
      const uint8_t* p = &img.px[(size_t(y) * 40 + x) * 4];
      EXPECT_EQ((Rgb8{p[0], p[1], p[2]}), want) << x << "," << y;
    }
}

TEST(CullingAnalysis, JsonHasEveryStatistic) {
  SyntheticView s;
  addRandomLights(s, 20, 12);
  const CullingInputs in = s.inputs(kDefaultTileCapacity, true);
  const CullingAnalysis a = analyzeCulling(in, fakeReadback(in, cullingReference(in)));
  for (const char* key :
       {"tiles", "lights_per_tile_mean", "lights_per_tile_max", "overflow_tiles", "false_positive_rate",
        "false_positives", "false_negatives", "dropped_by_overflow", "memory_bytes", "tile_size", "aabb",
        "light_culling", "hard_mismatches", "borderline_mismatches"})
    EXPECT_TRUE(a.json.contains(key)) << key;
  EXPECT_EQ(a.json["tiles"], 12u);
  EXPECT_EQ(a.json["memory_bytes"], cullingMemoryBytes(64, 48, 16, 32));
  EXPECT_EQ(a.json["aabb"], true);
  EXPECT_EQ(a.json["tile_size"], 16u);
  EXPECT_EQ(a.stats.falseNegatives, 0u);
}

}  // namespace
}  // namespace hb
