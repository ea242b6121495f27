// CPU-side ray analysis: accounting, the oracle, the reference surface and the accuracy figures,
// on hand-made readbacks and small scenes with known answers.
#include "analysis/ray_analysis.h"

#include <array>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "scene/camera.h"
#include "shared/gpu_types.h"

namespace hb {
namespace {

// The shadow pass's texel (shadows_common.glsl.inc): 16-bit counts, two to a word.
std::array<uint32_t, 4> pack(uint32_t traced, uint32_t normal, uint32_t range, uint32_t atLight, uint32_t noShadow,
                             uint32_t listed) {
  return {traced | listed << 16, normal | range << 16, atLight | noShadow << 16, 0u};
}

void append(std::vector<uint32_t>& v, const std::array<uint32_t, 4>& t) { v.insert(v.end(), t.begin(), t.end()); }

TEST(RayAccounting, UnpacksEveryFieldOfTheTexel) {
  const auto t = pack(4096, 1, 2, 3, 65535, 4000);
  const PixelAccount a = unpackAccount(t.data());
  EXPECT_EQ(a.traced, 4096u);
  EXPECT_EQ(a.listed, 4000u);
  EXPECT_EQ(a.byNormal, 1u);
  EXPECT_EQ(a.byRange, 2u);
  EXPECT_EQ(a.atLight, 3u);
  EXPECT_EQ(a.noShadow, 65535u);
}

// A 4x2 image in two 2x2 tiles, 5 scene lights: tile 0 kept 4 of which 3 were stored (overflow),
// tile 1 kept 2. Pixel (3, 1) is sky.
TEST(RayAccounting, EveryCandidateLandsInExactlyOneBucket) {
  const uint32_t w = 4, h = 2, tile = 2, lights = 5;
  CullingReadback c;
  c.tilesX = 2;
  c.tilesY = 1;
  c.capacity = 3;
  c.offset = {0, 3};
  c.count = {3, 2};
  c.total = {4, 2};
  c.indices = {0, 1, 2, 3, 4, 0};
  std::vector<float> depth = {0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.0f};
  ShadowReadback s;
  // Pixels (x, y) row by row: x 0-1 in tile 0 (3 stored), x 2-3 in tile 1 (2 stored).
  for (const auto& t : {pack(3, 0, 0, 0, 0, 3), pack(1, 2, 0, 0, 0, 3), pack(0, 0, 2, 0, 0, 2), pack(1, 0, 0, 1, 0, 2),
                        pack(2, 0, 0, 0, 1, 3), pack(0, 1, 1, 1, 0, 3), pack(2, 0, 0, 0, 0, 2), pack(0, 0, 0, 0, 0, 0)})
    append(s.accounting, t);
  const RayAccounting r = accountRays(s, c, depth, w, h, tile, lights);
  EXPECT_EQ(r.candidates, 7u * 5u);
  EXPECT_EQ(r.culledByTile, 4u * 1u + 3u * 3u);  // 4 pixels in tile 0 lose 1, 3 in tile 1 lose 3
  EXPECT_EQ(r.droppedByOverflow, 4u * 1u);
  EXPECT_EQ(r.traced, 3u + 1 + 1 + 2 + 2);
  EXPECT_EQ(r.culledByNormal, 2u + 1);
  EXPECT_EQ(r.culledByRange, 2u + 1);
  EXPECT_EQ(r.atLight, 1u + 1);
  EXPECT_EQ(r.noShadow, 1u);
  EXPECT_EQ(r.culledByZbin, 0u);
  EXPECT_EQ(r.walkMismatches, 0u);
  EXPECT_TRUE(r.addsUp());
  ASSERT_EQ(r.histogram.size(), 4u);  // 0..3 rays: up to the most any pixel traced
  EXPECT_EQ(r.histogram[0], 2u);      // pixels (2,0) and (1,1); sky is not counted
  EXPECT_EQ(r.histogram[1], 2u);
  EXPECT_EQ(r.histogram[2], 2u);
  EXPECT_EQ(r.histogram[3], 1u);
  EXPECT_EQ(r.perPixel[0], 3u);
  EXPECT_EQ(r.perPixel[7], 0u);
  const nlohmann::json j = toJson(r);
  for (const char* key :
       {"candidates", "culled_by_tile", "dropped_by_overflow", "culled_by_zbin", "culled_by_range", "culled_by_normal",
        "at_light", "no_shadow", "traced", "walk_mismatches", "per_pixel_histogram"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["per_pixel_histogram"].size(), 4u);
  EXPECT_EQ(j["traced"].get<uint64_t>(), 9u);
}

TEST(RayAccounting, HeatmapMapsItsMaximumToRedCappedAt32ForTileLists) {
  const std::vector<uint32_t> counts = {0, 10, 32, 40};
  ImageRGBA8 img = rayHeatmap(counts, 4, 1, 10);
  EXPECT_EQ(img.px[4 * 1 + 0], 255);  // 10 of 10: red
  EXPECT_EQ(img.px[4 * 1 + 1], 0);
  EXPECT_EQ(rayHeatmapMax(true, 100, counts), 32u);  // capped lists: 32 is the most a pixel traces
  EXPECT_EQ(rayHeatmapMax(true, 10, counts), 10u);
  EXPECT_EQ(rayHeatmapMax(false, 100, counts), 40u);  // uncapped: the most any pixel traced
  img = rayHeatmap(counts, 4, 1, rayHeatmapMax(true, 100, counts));
  EXPECT_EQ(img.px[4 * 2 + 0], 255);
  EXPECT_EQ(img.px[4 * 2 + 1], 0);
  EXPECT_NE(img.px[4 * 1 + 0], 255);
}

// A zbin readback: tile 0 holds sorted lights 1, 4, 7 (scene 5, 2, 0); a pixel range [2, 7) walks
// only sorted light 4, [0, 16) all three, an empty range none.
TEST(CullingReadback, PixelSliceOfZbinListsIsTheRangeOfSortedIndices) {
  CullingReadback c;
  c.lists = LightLists::Zbin;
  c.tilesX = c.tilesY = 1;
  c.offset = {0};
  c.count = c.total = {3};
  c.sorted = {1, 4, 7};
  c.indices = {5, 2, 0};
  EXPECT_EQ(c.pixelSlice(0, 2u | 7u << 16), std::make_pair(1u, 2u));
  EXPECT_EQ(c.pixelSlice(0, 0u | 16u << 16), std::make_pair(0u, 3u));
  EXPECT_EQ(c.pixelSlice(0, 0u), std::make_pair(0u, 0u));
  EXPECT_EQ(c.pixelSlice(0, 8u | 9u << 16).first, c.pixelSlice(0, 8u | 9u << 16).second);
  c.lists = LightLists::Bitmask;  // the whole tile whatever the range
  EXPECT_EQ(c.pixelSlice(0, 2u | 7u << 16), std::make_pair(0u, 3u));
}

TEST(RayEfficiency, IsOracleOverTracedAndOneWhenNothingIsTraced) {
  EXPECT_DOUBLE_EQ(rayEfficiency(30, 40), 0.75);
  EXPECT_DOUBLE_EQ(rayEfficiency(0, 0), 1.0);
}

// ---- reference surface, oracle, accuracy on an analytic plane ----------------------------------

// A quad in z = 0 (facing +z), camera at (0, 0, 5) looking down -z, 64x36. Depth is computed in
// double from the projection (depth = -C + D / 5 at every pixel, the plane is parallel to the image)
// and rounded once to float, as a perfect rasteriser would.
struct PlaneFixture {
  uint32_t w = 64, h = 36;
  Scene scene;
  glm::dmat4 view, proj;
  std::vector<float> depth;
  ReconstructionCamera<double> cam;
  PlaneFixture() {
    scene.name = "test-plane";
    const glm::vec3 n(0, 0, 1);
    for (glm::vec3 p : {glm::vec3(-10, -10, 0), glm::vec3(10, -10, 0), glm::vec3(10, 10, 0), glm::vec3(-10, 10, 0)})
      scene.vertices.push_back({p, n, {0, 0}});
    scene.indices = {0, 1, 2, 0, 2, 3};
    scene.meshes.push_back({"plane", {{0, 6, 0, 4, 0}}});
    scene.instances.push_back({0, glm::mat4(1.0f)});
    scene.materials.push_back({});
    view = glm::dmat4(lookAt({0, 0, 5}, {0, 0, 0}, {0, 1, 0}));
    proj = reverseZProjectionD(double(w) / h, 1.0471975512, 0.1, 1000.0);
    cam = reconstructionCamera<double>(view, proj, w, h);
    depth.assign(size_t(w) * h, float(-proj[2][2] + proj[3][2] / 5.0));
    depth[0] = 0.0f;  // one sky pixel
  }
};

TEST(ReferenceSurface, FindsThePlaneAndItsNormalFacingTheCamera) {
  PlaneFixture f;
  const Bvh bvh = buildBvh(f.scene);
  const ReferenceSurface s = referenceSurface(bvh, f.depth, f.cam);
  EXPECT_EQ(s.state[0], SurfaceState::Sky);
  EXPECT_EQ(s.matched, uint64_t(f.w) * f.h - 1);
  EXPECT_EQ(s.unmatched, 0u);
  for (size_t i = 1; i < s.state.size(); ++i) {
    ASSERT_EQ(s.normal[i], glm::dvec3(0, 0, 1));  // cross of axis-aligned edges: exact
    // The hit lies on z = 0 up to the double rounding of eye + t*dir (|coordinates| <= 6).
    ASSERT_NEAR(s.position[i].z, 0.0, 1e-14);
  }
}

TEST(Oracle, CountsLightsInRangeInsideTheConeAndInFrontOfTheSurface) {
  PlaneFixture f;
  auto point = [](glm::vec3 p, float range) {
    Light l;
    l.position = p;
    l.range = range;
    return l;
  };
  f.scene.lights.push_back(point({0, 0, 1}, 100));   // in front, in range of everything: counts
  f.scene.lights.push_back(point({0, 0, -1}, 100));  // behind the plane: N.L < 0
  f.scene.lights.push_back(point({0, 0, 1}, 0.5f));  // in front, range reaches no pixel (>= 1 m away)
  Light noShadow = point({0, 0, 1}, 100);
  noShadow.castShadows = false;  // visible without a ray
  f.scene.lights.push_back(noShadow);
  Light spot = point({0, 0, 1}, 100);  // straight down at the plane, 45 degree cone:
  spot.type = LightType::Spot;         // reaches |x|,|y| < 1 only
  spot.direction = {0, 0, -1};
  spot.outerConeAngle = 0.785398163f;
  f.scene.lights.push_back(spot);
  Light sun;
  sun.type = LightType::Directional;
  sun.direction = {0, 0.6f, -0.8f};  // shines onto the +z face
  f.scene.lights.push_back(sun);
  const ReferenceSurface s = referenceSurface(buildBvh(f.scene), f.depth, f.cam);
  const OracleRays o = oracleRays(f.scene, s);
  uint64_t expected = 0;
  for (size_t i = 1; i < s.state.size(); ++i) {
    const glm::dvec3 p = s.position[i];
    const bool inCone = std::hypot(p.x, p.y) < 1.0;  // tan 45 * 1 m
    const uint32_t want = 2 + (inCone ? 1 : 0);      // the first point light, the sun, maybe the spot
    ASSERT_EQ(o.perPixel[i], want) << "pixel " << i;
    expected += want;
  }
  EXPECT_EQ(o.perPixel[0], 0u);
  EXPECT_EQ(o.total, expected);
  EXPECT_EQ(o.pixelsWithoutNormal, 0u);
}

TEST(NormalAccuracy, MeasuresAnglesAndTheImageDifference) {
  PlaneFixture f;
  const ReferenceSurface s = referenceSurface(buildBvh(f.scene), f.depth, f.cam);
  const size_t n = s.state.size();
  std::vector<float> normals(4 * n, 0.0f);
  // Every pixel tilted by 10 degrees about x, except pixel 1 (no reconstruction).
  const double a = 10.0 / 57.29577951308232;
  for (size_t i = 2; i < n; ++i) {
    normals[4 * i + 1] = float(std::sin(a));
    normals[4 * i + 2] = float(std::cos(a));
  }
  const NormalAccuracy acc = normalAccuracy(normals, s);
  EXPECT_EQ(acc.compared, n - 2);
  EXPECT_EQ(acc.withoutReconstruction, 1u);
  EXPECT_EQ(acc.withoutReference, 0u);
  // float(sin a), float(cos a): the angle is 10 degrees to a few float ulps (~1e-7 rad ~ 1e-5 deg).
  EXPECT_NEAR(acc.meanAngleDeg, 10.0, 1e-5);
  EXPECT_NEAR(acc.p95AngleDeg, 10.0, 1e-5);
  EXPECT_NEAR(acc.maxAngleDeg, 10.0, 1e-5);
  // rgb difference: 0.5 * (0, sin a, 1 - cos a), averaged over 3 channels.
  EXPECT_NEAR(acc.meanImageDifference, 0.5 * (std::sin(a) + 1.0 - std::cos(a)) / 3.0, 1e-7);
  EXPECT_EQ(acc.angleDeg[1], 0.0f);
  EXPECT_TRUE(toJson(acc).contains("mean_image_difference"));
}

TEST(PositionAccuracy, IsZeroForTheReferenceItselfAndRelativeToTheDistance) {
  PlaneFixture f;
  const size_t n = size_t(f.w) * f.h;
  std::vector<float> positions(4 * n, 0.0f);
  for (uint32_t y = 0; y < f.h; ++y)
    for (uint32_t x = 0; x < f.w; ++x) {
      const size_t i = size_t(y) * f.w + x;
      if (i == 0) continue;
      glm::dvec3 p = worldFromDepth<double>(f.cam, x, y, double(f.depth[i]));
      if (i == 5) p.z += 1e-3 * glm::length(p - glm::dvec3(0, 0, 5));  // 1e-3 relative error, exactly
      positions[4 * i] = float(p.x), positions[4 * i + 1] = float(p.y), positions[4 * i + 2] = float(p.z);
      positions[4 * i + 3] = 1.0f;
    }
  const PositionAccuracy acc = positionAccuracy(positions, f.depth, f.cam);
  EXPECT_EQ(acc.compared, n - 1);
  EXPECT_EQ(acc.nonFinite, 0u);
  // Rounding each coordinate to float: <= 2^-24 |p| per coordinate, |p| <= 1.3 * distance here.
  EXPECT_NEAR(acc.maxRelative, 1e-3, 1e-6);
  EXPECT_NEAR(acc.relative[5], 1e-3, 1e-6);
  EXPECT_LT(acc.relative[6], 4e-7);
  EXPECT_GT(acc.meanRelative, 1e-3 / double(n) * 0.99);
}

// compareShadows on a hand-made readback: the CPU repeats the GPU's decisions and flags a wrong bit.
TEST(CompareShadows, AgreesWithAConsistentReadbackAndFlagsAWrongBit) {
  PlaneFixture f;
  Light front;
  front.position = {0, 0, 2};
  front.range = 100;
  Light back = front;
  back.position = {0, 0, -2};
  f.scene.lights = {front, back};
  // An occluder square above the centre of the plane, between it and the front light.
  const uint32_t base = uint32_t(f.scene.vertices.size());
  for (glm::vec3 p :
       {glm::vec3(-0.5f, -0.5f, 1), glm::vec3(0.5f, -0.5f, 1), glm::vec3(0.5f, 0.5f, 1), glm::vec3(-0.5f, 0.5f, 1)})
    f.scene.vertices.push_back({p, {0, 0, 1}, {0, 0}});
  for (uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u}) f.scene.indices.push_back(k);  // relative to vertexOffset
  f.scene.meshes[0].primitives.push_back({6, 6, base, 4, 0});
  const Bvh bvh = buildBvh(f.scene);
  // Two pixels: (10, 10) far from the occluder's shadow, the centre pixel in it. One tile holds both lights.
  const uint32_t w = 2, h = 1;
  ShadowReadback s;
  s.positions = {3, 1.5f, 0, 1, 0, 0, 0, 1};
  s.normals = {0, 0, 1, 0, 0, 0, 1, 0};
  s.visibility = {0b01, 0b00};  // the front light lights (3, 1.5); the back light faces away
  CullingReadback c;
  c.tilesX = c.tilesY = 1;
  c.capacity = 32;
  c.offset = {0};
  c.count = {2};
  c.total = {2};
  c.indices = {0, 1};
  ShadowComparison cmp = compareShadows(f.scene, bvh, s, c, w, h, 2, false);
  EXPECT_EQ(cmp.pairs, 4u);
  EXPECT_EQ(cmp.rays, 2u);  // the back light is culled by N.L at both pixels
  EXPECT_EQ(cmp.mismatches, 0u);
  EXPECT_EQ(cmp.visibility[0], 0b01u);
  EXPECT_EQ(cmp.visibility[1], 0b00u);
  s.visibility[1] = 0b01;  // a light leak under the occluder
  cmp = compareShadows(f.scene, bvh, s, c, w, h, 2, false);
  EXPECT_EQ(cmp.mismatches, 1u);
  EXPECT_EQ(cmp.unexplained(), 1u);
}

}  // namespace
}  // namespace hb
