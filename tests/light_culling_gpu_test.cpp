// GPU light culling (thesis 4.2.3) on the real device against the CPU reference of the same
// method (cull_ref.h in float, via culling_analysis.h) and against the exact light sets. Small
// resolutions keep every test within a few seconds on lavapipe.
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "analysis/culling_analysis.h"
#include "frame/renderer.h"
#include "gpu_fixture.h"
#include "scene/atrium.h"
#include "scene/camera.h"
#include "scene/mesh_builder.h"

namespace hb {
namespace {

constexpr double kPi = 3.14159265358979323846;

// One culled frame and what the analysis needs to look at it.
struct CullRun {
  std::vector<float> depth;
  CullingReadback gpu;
  CullingInputs in;
  CullingAnalysis analysis;
};

// Renders one frame of `scene` (no shadows: only the depth prepass and the culling passes) and
// analyses its culling. `scene` must outlive the result (in.lights points into it).
std::unique_ptr<CullRun> cull(const VulkanContext& ctx, const Scene& scene, uint32_t width, uint32_t height,
                              uint32_t tileSize, bool lightCulling = true, bool aabb = false,
                              uint32_t depthSlices = 0) {
  RenderSettings rs{.width = width, .height = height, .tileSize = tileSize, .lightCulling = lightCulling, .aabb = aabb};
  rs.depthSlices = depthSlices;
  rs.effects.add(EffectSource::Config, "test", {{"shadows", false}});
  Renderer renderer(ctx, scene, rs);
  renderer.renderFrame(true);
  auto run = std::make_unique<CullRun>();
  run->depth = renderer.readDepth();
  run->gpu = renderer.readCulling();
  run->in.depth = &run->depth;
  run->in.lights = &scene.lights;
  run->in.view = renderer.view();
  run->in.proj = renderer.proj();
  run->in.width = width;
  run->in.height = height;
  run->in.tileSize = tileSize;
  run->in.aabb = aabb;
  run->in.lightCulling = lightCulling;
  run->in.depthSlices = depthSlices;
  run->in.capacity = run->gpu.capacity;
  run->analysis = analyzeCulling(run->in, run->gpu);
  return run;
}

std::string label(const CullingInputs& in) {
  return std::to_string(in.width) + "x" + std::to_string(in.height) + " tile " + std::to_string(in.tileSize) +
         (in.lightCulling ? "" : " culling off") + (in.aabb ? " aabb" : "") +
         (in.depthSlices ? " slices " + std::to_string(in.depthSlices) : "");
}

// The GPU lists equal the float reference (up to rounding-level borderline decisions) and miss
// no light that meets the tile (outside overflowing tiles).
void expectMatchesReference(const CullRun& r) {
  const CullingComparison& c = r.analysis.comparison;
  EXPECT_EQ(c.hardMismatches, 0u) << label(r.in);
  EXPECT_EQ(c.malformedTiles, 0u) << label(r.in);
  EXPECT_EQ(c.totalMismatchTiles, 0u) << label(r.in);
  for (const auto& m : c.mismatches)
    if (!m.borderline)
      ADD_FAILURE() << label(r.in) << ": tile " << m.tile << " light " << m.light
                    << (m.gpuKept ? " only on GPU" : " only on CPU") << ", margin " << m.margin << " > bound "
                    << m.bound;
  EXPECT_EQ(r.analysis.stats.falseNegatives, 0u) << label(r.in);
  EXPECT_EQ(r.analysis.stats.missedNeeded, 0u) << label(r.in) << ": a light that reaches a pixel was dropped";
  if (r.in.depthSlices == 0) {
    EXPECT_EQ(r.analysis.stats.slicedAway, 0u) << label(r.in);
  }
}

Scene sceneWithCamera(glm::vec3 eye, glm::vec3 target, float znear = 0.1f) {
  Scene s;
  s.name = "culling-test";
  s.materials.push_back({});
  Camera cam;
  cam.view = lookAt(eye, target, {0.0f, 1.0f, 0.0f});
  cam.yfov = 1.0f;
  cam.znear = znear;
  cam.zfar = 100.0f;
  s.cameras.push_back(cam);
  return s;
}

Light rangedPointLight(glm::vec3 p, float range) { return Light{.position = p, .range = range}; }

Light spotLight(glm::vec3 p, glm::vec3 dir, float range, float outer) {
  Light l = rangedPointLight(p, range);
  l.type = LightType::Spot;
  l.direction = glm::normalize(dir);
  l.outerConeAngle = outer;
  l.innerConeAngle = 0.5f * outer;
  return l;
}

// A floor (y = 0), a back wall (z = -6) and a few random boxes; 20-60 random point and spot
// lights, among them spots with a 90-degree outer angle and spots whose axis is parallel to a
// plane normal (the floor's, the wall's, and the camera's view direction = the tiles' near/far
// plane normals).
Scene randomScene(uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const glm::vec3 eye(0.0f, 3.0f, 8.0f), target(0.0f, 0.5f, 0.0f);
  Scene s = sceneWithCamera(eye, target);
  MeshBuilder mb("random");
  addQuad(mb, 0, {-10, 0, -10}, {10, 0, -10}, {10, 0, 10}, {-10, 0, 10}, {0, 1, 0});
  addQuad(mb, 0, {-10, 0, -6}, {10, 0, -6}, {10, 8, -6}, {-10, 8, -6}, {0, 0, 1});
  const int boxes = 3 + int(rng() % 4);
  for (int i = 0; i < boxes; ++i) {
    const glm::dvec3 lo(-5.0 + 9.0 * u(rng), 0.0, -5.0 + 8.0 * u(rng));
    addBox(mb, 0, lo, lo + glm::dvec3(0.3 + 1.5 * u(rng), 0.3 + 2.0 * u(rng), 0.3 + 1.5 * u(rng)));
  }
  mb.appendTo(s);
  const uint32_t count = 20 + rng() % 41;
  const glm::vec3 forward = glm::normalize(target - eye);
  for (uint32_t i = 0; i < count; ++i) {
    const glm::vec3 p(-7.0f + 14.0f * u(rng), 0.1f + 5.0f * u(rng), -5.5f + 11.0f * u(rng));
    const float range = 0.3f + 4.0f * u(rng);
    const glm::vec3 randomDir = glm::vec3(u(rng), u(rng), u(rng)) - 0.5f;
    switch (i % 6) {
      case 0:
      case 1: s.lights.push_back(rangedPointLight(p, range)); break;
      case 2: s.lights.push_back(spotLight(p, randomDir, range, 0.1f + 1.3f * u(rng))); break;
      case 3: s.lights.push_back(spotLight(p, randomDir, range, float(kPi / 2))); break;  // 90 degrees
      case 4:
        s.lights.push_back(spotLight(p, i % 12 == 4 ? glm::vec3(0, -1, 0) : glm::vec3(0, 0, -1), range, 0.6f));
        break;
      default: s.lights.push_back(spotLight(p, forward, range, 0.4f + 0.8f * u(rng))); break;
    }
  }
  return s;
}

class LightCullingGpuTest : public testing::GpuTest {};

// The atrium (smallest tessellation, 40 lights) at 320x180: planes only, planes + AABB, and
// culling off, at one tile size.
void checkAtrium(const VulkanContext& ctx, uint32_t tileSize) {
  static const Scene atrium = [] {
    AtriumParams ap;
    ap.triangleScale = 0.25;
    ap.lightCount = 40;
    return makeAtrium(ap);
  }();
  uint64_t fp[2] = {};
  for (bool aabb : {false, true}) {
    const auto r = cull(ctx, atrium, 320, 180, tileSize, true, aabb);
    expectMatchesReference(*r);
    fp[aabb] = r->analysis.stats.falsePositives;
    std::printf(
        "atrium 320x180 tile %u aabb %d: FP rate %.4f (%llu of %llu), mean %.2f max %u lights/tile, "
        "borderline %llu\n",
        tileSize, int(aabb), r->analysis.stats.falsePositiveRate, (unsigned long long)fp[aabb],
        (unsigned long long)r->analysis.stats.storedPairs, r->analysis.stats.meanLightsPerTile,
        r->analysis.stats.maxLightsPerTile, (unsigned long long)r->analysis.comparison.borderlineMismatches);
  }
  EXPECT_LE(fp[1], fp[0]) << "tile " << tileSize << ": the AABB test only ever removes lights";
  // Culling off: every tile lists every light (the first 32 stored), sky tiles included.
  const auto off = cull(ctx, atrium, 320, 180, tileSize, false, false);
  expectMatchesReference(*off);
  for (uint32_t t : off->gpu.total) ASSERT_EQ(t, 40u);
  EXPECT_GT(off->analysis.stats.falsePositiveRate, 0.5);
  std::printf("atrium 320x180 tile %u culling off: FP rate %.4f\n", tileSize, off->analysis.stats.falsePositiveRate);
}

TEST_F(LightCullingGpuTest, AtriumListsEqualTheCpuReferenceAtTileSize8) { checkAtrium(*ctx, 8); }
TEST_F(LightCullingGpuTest, AtriumListsEqualTheCpuReferenceAtTileSize16) { checkAtrium(*ctx, 16); }
TEST_F(LightCullingGpuTest, AtriumListsEqualTheCpuReferenceAtTileSize32) { checkAtrium(*ctx, 32); }

TEST_F(LightCullingGpuTest, RandomScenesMatchTheCpuReferenceAndNeverMissALight) {
  for (uint32_t seed : {1u, 2u, 3u}) {
    const Scene scene = randomScene(seed);
    for (uint32_t tileSize : {8u, 16u}) {
      uint64_t fp[2] = {};
      for (bool aabb : {false, true}) {
        const auto r = cull(*ctx, scene, 256, 144, tileSize, true, aabb);
        SCOPED_TRACE("seed " + std::to_string(seed));
        expectMatchesReference(*r);
        EXPECT_GT(r->analysis.stats.exactPairs, 100u);  // the lights must actually reach tiles
        fp[aabb] = r->analysis.stats.falsePositives;
      }
      EXPECT_LE(fp[1], fp[0]) << "seed " << seed << " tile " << tileSize;
    }
  }
}

TEST_F(LightCullingGpuTest, ResolutionNotAMultipleOfTheTileSizeCullsThePartialTiles) {
  const Scene scene = randomScene(4);
  for (uint32_t tileSize : {16u, 32u}) {
    const auto r = cull(*ctx, scene, 100, 75, tileSize, true, true);
    EXPECT_EQ(r->gpu.tilesX, tileCount(100, tileSize));
    EXPECT_EQ(r->gpu.tilesY, tileCount(75, tileSize));
    expectMatchesReference(*r);
  }
}

TEST_F(LightCullingGpuTest, SkyOnlyTilesGetNoLights) {
  // A wall at z = -5 covering exactly the left half of the view (x <= 0); sky elsewhere. One
  // light whose range covers the whole view.
  Scene scene = sceneWithCamera({0, 0, 0}, {0, 0, -1});
  MeshBuilder mb("half");
  addQuad(mb, 0, {-20, -20, -5}, {0, -20, -5}, {0, 20, -5}, {-20, 20, -5}, {0, 0, 1});
  mb.appendTo(scene);
  scene.lights.push_back(rangedPointLight({0, 0, -3}, 50.0f));
  const auto r = cull(*ctx, scene, 128, 64, 16);
  expectMatchesReference(*r);
  const CullingReference& ref = r->analysis.reference;
  uint32_t sky = 0, lit = 0;
  for (uint32_t ty = 0; ty < r->gpu.tilesY; ++ty)
    for (uint32_t tx = 0; tx < r->gpu.tilesX; ++tx) {
      const size_t t = size_t(ty) * r->gpu.tilesX + tx;
      const auto range = tileDepthRange(r->depth, 128, 64, tileRect(tx, ty, 16, 128, 64));
      if (range.empty()) {
        ++sky;
        EXPECT_EQ(r->gpu.total[t], 0u) << "sky tile " << tx << "," << ty;
        EXPECT_TRUE(ref.exact[t].empty());
      } else {
        ++lit;
        EXPECT_EQ(r->gpu.total[t], 1u) << "tile " << tx << "," << ty;
      }
    }
  EXPECT_EQ(sky, 16u);  // the right 4 of 8 tile columns, 4 rows
  EXPECT_EQ(lit, 16u);
}

TEST_F(LightCullingGpuTest, FortyLightsOnOneTileOverflowAndKeepTheLowestIndices) {
  // A wall filling the view at distance 5; 40 tiny lights in front of the centre of tile (3, 1)
  // of a 128x64 image at 16 px: that tile keeps all 40 (total 40) and stores 32.
  Scene scene = sceneWithCamera({0, 0, 0}, {0, 0, -1});
  MeshBuilder mb("wall");
  addQuad(mb, 0, {-20, -20, -5}, {20, -20, -5}, {20, 20, -5}, {-20, 20, -5}, {0, 0, 1});
  mb.appendTo(scene);
  // Centre of tile (3, 1), i.e. pixel (56, 24), on the view ray at distance 4.9: ndc = 2*px/W - 1,
  // view = (ndc.x/A, ndc.y/B, -1) * 4.9.
  const glm::mat4 proj = reverseZProjection(2.0f, 1.0f, 0.1f, 100.0f);
  const glm::vec3 ray((2.0f * 56.0f / 128.0f - 1.0f) / proj[0][0], (2.0f * 24.0f / 64.0f - 1.0f) / proj[1][1], -1.0f);
  for (int i = 0; i < 40; ++i) scene.lights.push_back(rangedPointLight(ray * 4.9f, 0.15f));  // view = world here
  const auto r = cull(*ctx, scene, 128, 64, 16);
  expectMatchesReference(*r);
  const size_t tile = 1 * 8 + 3;
  EXPECT_EQ(r->gpu.total[tile], 40u);
  ASSERT_EQ(r->gpu.count[tile], 32u);
  std::vector<uint32_t> stored(r->gpu.indices.begin() + r->gpu.offset[tile],
                               r->gpu.indices.begin() + r->gpu.offset[tile] + 32);
  std::sort(stored.begin(), stored.end());
  for (uint32_t i = 0; i < 32; ++i) EXPECT_EQ(stored[i], i);
  EXPECT_EQ(r->analysis.reference.exact[tile].size(), 40u);
  EXPECT_GE(r->analysis.stats.overflowTiles, 1u);
  EXPECT_GE(r->analysis.stats.droppedByOverflow, 8u);  // at least this tile's 8 unstored lights
  EXPECT_EQ(r->analysis.json["overflow_tiles"], r->analysis.stats.overflowTiles);
}

TEST_F(LightCullingGpuTest, LightWithRangeFromEquation41ReachesOnlyTilesWithinIt) {
  // A floor seen at a grazing angle; a 2 cd light 0.5 m above it: eq. 4.1 gives sqrt(50*2) = 10 m,
  // so near floor tiles keep it and the distant ones (the floor runs to 60 m) do not.
  Scene scene = sceneWithCamera({0, 1.5f, 0}, {0, 1.0f, -10});
  MeshBuilder mb("floor");
  addQuad(mb, 0, {-60, 0, -60}, {60, 0, -60}, {60, 0, 5}, {-60, 0, 5}, {0, 1, 0});
  mb.appendTo(scene);
  Light l = rangedPointLight({0, 0.5f, -4}, float(rangeFromIntensity(2.0)));
  l.intensity = 2.0f;
  l.rangeFromEq41 = true;
  scene.lights.push_back(l);
  ASSERT_FLOAT_EQ(l.range, 10.0f);
  const auto r = cull(*ctx, scene, 160, 96, 16, true, true);
  expectMatchesReference(*r);
  uint32_t keep = 0, cut = 0;  // floor tiles that keep the light / do not
  for (uint32_t ty = 0; ty < r->gpu.tilesY; ++ty)
    for (uint32_t tx = 0; tx < r->gpu.tilesX; ++tx) {
      if (tileDepthRange(r->depth, 160, 96, tileRect(tx, ty, 16, 160, 96)).empty()) continue;  // sky
      ++(r->gpu.total[size_t(ty) * r->gpu.tilesX + tx] ? keep : cut);
    }
  EXPECT_GT(keep, 0u);
  EXPECT_GT(cut, 0u);
}

TEST_F(LightCullingGpuTest, CameraInsideALightsSphereLightsEveryTile) {
  Scene scene = sceneWithCamera({1, 1, 1}, {1, 1, -4});
  MeshBuilder mb("wall");
  addQuad(mb, 0, {-20, -20, -4}, {20, -20, -4}, {20, 20, -4}, {-20, 20, -4}, {0, 0, 1});
  mb.appendTo(scene);
  scene.lights.push_back(rangedPointLight({1.2f, 0.9f, 1.1f}, 8.0f));       // the eye is inside; reaches the wall
  scene.lights.push_back(spotLight({1, 1, 1.5f}, {0, 0, -1}, 8.0f, 1.2f));  // behind the eye, aimed forward
  for (bool aabb : {false, true}) {
    const auto r = cull(*ctx, scene, 96, 64, 16, true, aabb);
    expectMatchesReference(*r);
    for (uint32_t t : r->gpu.total) EXPECT_GE(t, 1u);
    EXPECT_EQ(r->gpu.total[r->gpu.tilesX * 2 + 3], 2u);  // a central tile gets both
  }
}

TEST_F(LightCullingGpuTest, LightStraddlingTheNearPlaneIsKeptWhereItReachesTheSurface) {
  // znear 0.1; a wall 0.4 m away; a light centred on the near plane with range 0.35 (from
  // z = +0.25 behind the near plane to z = -0.45, past the wall).
  Scene scene = sceneWithCamera({0, 0, 0}, {0, 0, -1}, 0.1f);
  MeshBuilder mb("wall");
  addQuad(mb, 0, {-5, -5, -0.4}, {5, -5, -0.4}, {5, 5, -0.4}, {-5, 5, -0.4}, {0, 0, 1});
  mb.appendTo(scene);
  scene.lights.push_back(rangedPointLight({0, 0, -0.1f}, 0.35f));
  for (bool aabb : {false, true}) {
    const auto r = cull(*ctx, scene, 128, 64, 16, true, aabb);
    expectMatchesReference(*r);
    const size_t centre = 2 * 8 + 3;  // tile (3, 2) touches the image centre (64, 32)
    EXPECT_EQ(r->gpu.total[centre], 1u);
    // The corner tile's wall patch is out of range (0.57 m away). The plane test alone keeps the
    // light there (near the eye the side planes all pass within 0.35 m of it); the AABB removes it.
    EXPECT_TRUE(r->analysis.reference.exact[0].empty());
    if (aabb) {
      EXPECT_EQ(r->gpu.total[0], 0u);
    }
  }
}

// ---- depth slices (2.5D culling, beyond the thesis) ------------------------------------------------

// A tile partly on a near box face (z = -2) and partly on a far wall (z = -20): its frustum spans
// 2..20 m. A light at 10 m with range 2 lies in the empty gap: the frustum test keeps it, the slab
// test drops it (32 slabs of 18/32 m: the light covers slabs 10..17, the pixels only 0 and 31);
// a light at 19 m with range 2 reaches the wall and stays. 128x64, yfov 1 rad: at 2 m a pixel is
// 2·tan(0.5)·2/64 = 0.034 m wide, so the box edge at x = -0.25 m falls 7 px left of the image
// centre, inside tile column 3 (pixels 48..63).
TEST_F(LightCullingGpuTest, DepthSlicesDropALightInTheGapBetweenTwoSurfacesAndKeepOneOnTheWall) {
  Scene scene = sceneWithCamera({0, 0, 0}, {0, 0, -1});
  MeshBuilder mb("step");
  addQuad(mb, 0, {-40, -40, -20}, {40, -40, -20}, {40, 40, -20}, {-40, 40, -20}, {0, 0, 1});
  addQuad(mb, 0, {-5, -5, -2}, {-0.25, -5, -2}, {-0.25, 5, -2}, {-5, 5, -2}, {0, 0, 1});
  mb.appendTo(scene);
  scene.lights.push_back(rangedPointLight({0, 0, -10}, 2.0f));
  scene.lights.push_back(rangedPointLight({0, 0, -19}, 2.0f));
  for (uint32_t slices : {0u, 32u}) {
    const auto r = cull(*ctx, scene, 128, 64, 16, true, false, slices);
    expectMatchesReference(*r);
    const size_t t = 1 * 8 + 3;  // row 1, column 3: box face and wall
    const auto range = tileDepthRange(r->depth, 128, 64, tileRect(3, 1, 16, 128, 64));
    ASSERT_FALSE(range.empty());
    const std::vector<uint32_t>& exact = r->analysis.reference.exact[t];
    EXPECT_EQ(exact, (std::vector<uint32_t>{0, 1}));                         // both meet the 2..20 m frustum
    EXPECT_EQ(r->analysis.reference.needed[t], (std::vector<uint32_t>{1}));  // only one reaches a pixel
    EXPECT_EQ(r->gpu.total[t], slices ? 1u : 2u) << "slices " << slices;
    if (slices) {
      EXPECT_GE(r->analysis.stats.slicedAway, 1u);
    }
  }
}

// The atrium and the random scenes with depth slices: the GPU equals the float reference, no light
// that reaches a pixel is lost, and slicing never adds a light (it only runs after the plane and
// AABB tests), so lights per tile and the lights that reach no pixel can only go down.
TEST_F(LightCullingGpuTest, DepthSlicesMatchTheCpuReferenceAndOnlyRemoveLights) {
  AtriumParams ap;
  ap.triangleScale = 0.25;
  ap.lightCount = 40;
  std::vector<Scene> scenes;
  scenes.push_back(makeAtrium(ap));
  for (uint32_t seed : {1u, 2u}) scenes.push_back(randomScene(seed));
  for (const Scene& scene : scenes)
    for (uint32_t tileSize : {8u, 16u, 32u})
      for (bool aabb : {false, true}) {
        const auto plain = cull(*ctx, scene, 256, 144, tileSize, true, aabb, 0);
        expectMatchesReference(*plain);
        for (uint32_t slices : {4u, 32u}) {
          const auto sliced = cull(*ctx, scene, 256, 144, tileSize, true, aabb, slices);
          SCOPED_TRACE(scene.name + " " + label(sliced->in));
          expectMatchesReference(*sliced);
          const CullStatistics &a = plain->analysis.stats, &b = sliced->analysis.stats;
          EXPECT_LE(b.meanLightsPerTile, a.meanLightsPerTile);
          EXPECT_LE(b.uselessPairs, a.uselessPairs);
          EXPECT_EQ(b.neededPairs, a.neededPairs);  // the same depth, the same lights
          for (size_t t = 0; t < plain->gpu.total.size(); ++t)
            EXPECT_LE(sliced->gpu.total[t], plain->gpu.total[t]) << "tile " << t;
          if (tileSize == 16 && !aabb)
            std::printf(
                "%s tile 16, %u slices: lights/tile %.3f -> %.3f, reaching no pixel %.1f %% -> %.1f %%, "
                "borderline %llu\n",
                scene.name.c_str(), slices, a.meanLightsPerTile, b.meanLightsPerTile, 100 * a.uselessRate,
                100 * b.uselessRate, (unsigned long long)sliced->analysis.comparison.borderlineMismatches);
        }
      }
}

}  // namespace
}  // namespace hb
