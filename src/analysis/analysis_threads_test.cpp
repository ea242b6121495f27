// The analyses of a frame on several threads (base/parallel.h parallelFor) give the serial run's
// result bit for bit, as parallel.h promises: every analysis that runs on threads, on the atrium
// seen from its camera, with the frame's readbacks made on the CPU. CI also runs these under
// ThreadSanitizer (scripts/sanitize.sh), which holds them to be free of data races.
#include <cstring>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "analysis/culling_analysis.h"
#include "analysis/ray_analysis.h"
#include "base/parallel_test_util.h"
#include "base/splitmix64.h"
#include "frame/renderer.h"
#include "reference/bvh.h"
#include "reference/reconstruct_ref.h"
#include "scene/atrium.h"
#include "scene/camera.h"

namespace hb {
namespace {

// 1 is the serial run; 2 is CI's cores; 7 divides neither the rows nor the tiles.
constexpr unsigned kThreadCounts[] = {2, 7};

// Equal as bytes: -0.0 differs from 0.0, and a NaN equals the same NaN.
template <typename T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// The atrium (a quarter of its triangles) from its camera at 64 x 40, with 24 of its lights, every
// fourth made a spot, and a sun. Depth is the double ray cast through each pixel centre, rounded
// once to float (what an exact rasteriser writes). The readbacks are those of a z-binned frame whose
// tile lists are the CPU reference's (no cap), whose pixel bin ranges and ray counts are drawn from
// a fixed seed, and whose shadow mask is the CPU's own with one bit flipped at every 7th lit pixel
// (mismatches, so that compareShadows explains them too).
struct AtriumFrame {
  static constexpr uint32_t kWidth = 64, kHeight = 40, kTileSize = 16;
  Scene scene;
  Bvh bvh;
  glm::mat4 view, proj;
  ReconstructionCamera<double> cam;
  std::vector<float> depth;
  CullingInputs culling;
  CullingReadback lists;
  ShadowReadback shadows;

  AtriumFrame() {
    AtriumParams params;
    params.triangleScale = 0.25;
    params.lightCount = 24;
    scene = makeAtrium(params);
    for (size_t i = 0; i < scene.lights.size(); i += 4) {
      scene.lights[i].type = LightType::Spot;
      scene.lights[i].direction = {0.0f, -1.0f, 0.0f};
    }
    Light sun;
    sun.type = LightType::Directional;
    sun.direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
    scene.lights.push_back(sun);
    bvh = buildBvh(scene);
    const Camera& camera = scene.cameras.at(0);
    view = camera.view;
    proj = reverseZProjection(float(kWidth) / kHeight, camera.yfov, camera.znear, camera.zfar);
    cam = reconstructionCamera<double>(glm::dmat4(view), glm::dmat4(proj), kWidth, kHeight);
    const glm::dvec3 eye(cam.viewInv[3]);
    depth.assign(size_t(kWidth) * kHeight, 0.0f);
    for (uint32_t y = 0; y < kHeight; ++y)
      for (uint32_t x = 0; x < kWidth; ++x) {
        // Scaled so that a step of 1 along it is 1 m of view depth (reference_surface.cpp).
        const double ndcX = std::fma((x + 0.5) / kWidth, 2.0, -1.0), ndcY = std::fma((y + 0.5) / kHeight, 2.0, -1.0);
        const glm::dvec3 dir(cam.viewInv * glm::dvec4(ndcX / cam.a, ndcY / cam.b, -1.0, 0.0));
        double t;
        if (bvh.closestHit(eye, dir, camera.znear, camera.zfar, t))
          depth[size_t(y) * kWidth + x] = float(cam.d / t - cam.c);
      }

    culling.depth = &depth;
    culling.lights = &scene.lights;
    culling.view = view;
    culling.proj = proj;
    culling.width = kWidth;
    culling.height = kHeight;
    culling.tileSize = kTileSize;
    culling.capacity = uint32_t(scene.lights.size());
    const CullingReference ref = [&] {
      const ScopedAnalysisThreads serial(1u);
      return cullingReference(culling);
    }();
    lists.lists = LightLists::Zbin;
    lists.tilesX = tileCount(kWidth, kTileSize);
    lists.tilesY = tileCount(kHeight, kTileSize);
    lists.capacity = uint32_t(scene.lights.size());
    for (const TileLightList& tile : ref.same) {
      lists.offset.push_back(uint32_t(lists.indices.size()));
      lists.count.push_back(uint32_t(tile.indices.size()));
      lists.total.push_back(tile.total);
      lists.indices.insert(lists.indices.end(), tile.indices.begin(), tile.indices.end());
    }
    lists.sorted = lists.indices;  // the sorted order is the scene's: ascending in every tile
    for (uint32_t i = 0; i < scene.lights.size(); ++i) lists.order.push_back(i);

    const size_t pixels = depth.size();
    const ReferenceSurface surface = [&] {
      const ScopedAnalysisThreads serial(1u);
      return referenceSurface(bvh, depth, cam);
    }();
    SplitMix64 rng{31};
    const uint32_t lightCount = uint32_t(scene.lights.size());
    shadows.positions.assign(4 * pixels, 0.0f);
    shadows.normals.assign(4 * pixels, 0.0f);
    shadows.ranges.assign(pixels, 0u);
    shadows.accounting.assign(4 * pixels, 0u);
    uint32_t longestWalk = 0;
    for (size_t i = 0; i < pixels; ++i) {
      const uint32_t lo = uint32_t(rng.next() % (lightCount + 1));
      const uint32_t hi = lo + uint32_t(rng.next() % (lightCount + 1 - lo));
      shadows.ranges[i] = lo | hi << 16;
      if (surface.state[i] == SurfaceState::Sky) continue;
      for (int k = 0; k < 3; ++k) {
        shadows.positions[4 * i + k] = float(surface.position[i][k]);
        shadows.normals[4 * i + k] = float(surface.normal[i][k]);
      }
      shadows.positions[4 * i + 3] = 1.0f;
      const uint32_t x = uint32_t(i % kWidth), y = uint32_t(i / kWidth);
      const auto [first, last] = lists.pixelSlice((y / kTileSize) * lists.tilesX + x / kTileSize, shadows.ranges[i]);
      longestWalk = std::max(longestWalk, last - first);
      // The walk's lights split at random into the buckets, so that the accounting adds up.
      uint32_t left = last - first;
      auto draw = [&] {
        const uint32_t k = uint32_t(rng.next() % (left + 1));
        left -= k;
        return k;
      };
      const uint32_t byNormal = draw(), byRange = draw(), atLight = draw(), noShadow = draw(), traced = left;
      shadows.accounting[4 * i] = traced | (last - first) << 16;
      shadows.accounting[4 * i + 1] = byNormal | byRange << 16;
      shadows.accounting[4 * i + 2] = atLight | noShadow << 16;
    }
    shadows.words = std::max(1u, (longestWalk + 31) / 32);
    shadows.visibility.assign(shadows.words * pixels, 0u);
    {
      const ScopedAnalysisThreads serial(1u);
      shadows.visibility = compareShadows(scene, bvh, shadows, lists, kWidth, kHeight, kTileSize, true).visibility;
    }
    size_t lit = 0;
    for (size_t i = 0; i < pixels; ++i)
      if (shadows.positions[4 * i + 3] == 1.0f && shadows.ranges[i] >> 16 > (shadows.ranges[i] & 0xFFFFu) &&
          lit++ % 7 == 0)
        shadows.visibility[i] ^= 1u;
  }
};

const AtriumFrame& atriumFrame() {
  static const AtriumFrame frame;
  return frame;
}

// fn's result with HYBRIDBENCH_THREADS=threads.
template <typename Fn>
auto onThreads(unsigned threads, Fn fn) {
  const ScopedAnalysisThreads scoped(threads);
  return fn();
}

TEST(AnalysisThreads, TheFrameHasSkyLightsInEveryTileAndShadowMismatches) {
  const AtriumFrame& f = atriumFrame();
  size_t sky = 0;
  for (float d : f.depth) sky += !(d > 0.0f);
  EXPECT_GT(sky, 0u);
  EXPECT_LT(sky, f.depth.size() / 2);
  EXPECT_EQ(f.lists.count.size(), 4u * 3u);
  for (uint32_t c : f.lists.count) EXPECT_GT(c, 0u);
  const ShadowComparison c = onThreads(
      1, [&] { return compareShadows(f.scene, f.bvh, f.shadows, f.lists, f.kWidth, f.kHeight, f.kTileSize, true); });
  EXPECT_GT(c.rays, 1000u);
  EXPECT_GT(c.mismatches, 10u);
}

TEST(AnalysisThreads, CullingReferenceIsTheSerialOneBitForBit) {
  const AtriumFrame& f = atriumFrame();
  const CullingReference serial = onThreads(1, [&] { return cullingReference(f.culling); });
  for (unsigned threads : kThreadCounts) {
    const CullingReference r = onThreads(threads, [&] { return cullingReference(f.culling); });
    ASSERT_EQ(r.same.size(), serial.same.size());
    for (size_t t = 0; t < serial.same.size(); ++t) {
      EXPECT_EQ(r.same[t].indices, serial.same[t].indices) << "tile " << t << ", " << threads << " threads";
      EXPECT_EQ(r.same[t].total, serial.same[t].total) << "tile " << t << ", " << threads << " threads";
    }
    EXPECT_EQ(r.sameAll, serial.sameAll) << threads << " threads";
    EXPECT_EQ(r.exact, serial.exact) << threads << " threads";
    EXPECT_EQ(r.needed, serial.needed) << threads << " threads";
  }
}

TEST(AnalysisThreads, ZbinMissedPairsAreTheSerialCount) {
  const AtriumFrame& f = atriumFrame();
  const uint64_t serial = onThreads(1, [&] { return zbinMissedPairs(f.culling, f.lists, f.shadows.ranges); });
  EXPECT_GT(serial, 0u);  // the drawn bin ranges leave out lights that reach their pixels
  for (unsigned threads : kThreadCounts)
    EXPECT_EQ(onThreads(threads, [&] { return zbinMissedPairs(f.culling, f.lists, f.shadows.ranges); }), serial)
        << threads << " threads";
}

TEST(AnalysisThreads, RayAccountingIsTheSerialOneBitForBit) {
  const AtriumFrame& f = atriumFrame();
  auto account = [&] {
    return accountRays(f.shadows, f.lists, f.depth, f.kWidth, f.kHeight, f.kTileSize, uint32_t(f.scene.lights.size()));
  };
  const RayAccounting serial = onThreads(1, account);
  EXPECT_TRUE(serial.addsUp());
  for (unsigned threads : kThreadCounts) {
    const RayAccounting r = onThreads(threads, account);
    EXPECT_EQ(toJson(r), toJson(serial)) << threads << " threads";
    EXPECT_EQ(r.perPixel, serial.perPixel) << threads << " threads";
  }
}

TEST(AnalysisThreads, ReferenceSurfaceAndOracleAreTheSerialOnesBitForBit) {
  const AtriumFrame& f = atriumFrame();
  const ReferenceSurface serial = onThreads(1, [&] { return referenceSurface(f.bvh, f.depth, f.cam); });
  const OracleRays serialOracle = onThreads(1, [&] { return oracleRays(f.scene, serial); });
  EXPECT_GT(serial.matched, f.depth.size() / 2);
  EXPECT_GT(serialOracle.total, 0u);
  for (unsigned threads : kThreadCounts) {
    const ReferenceSurface s = onThreads(threads, [&] { return referenceSurface(f.bvh, f.depth, f.cam); });
    EXPECT_TRUE(sameBits(s.state, serial.state)) << threads << " threads";
    EXPECT_TRUE(sameBits(s.position, serial.position)) << threads << " threads";
    EXPECT_TRUE(sameBits(s.normal, serial.normal)) << threads << " threads";
    EXPECT_EQ(s.matched, serial.matched);
    EXPECT_EQ(s.unmatched, serial.unmatched);
    const OracleRays o = onThreads(threads, [&] { return oracleRays(f.scene, serial); });
    EXPECT_EQ(o.perPixel, serialOracle.perPixel) << threads << " threads";
    EXPECT_EQ(o.total, serialOracle.total);
    EXPECT_EQ(o.pixelsWithoutNormal, serialOracle.pixelsWithoutNormal);
  }
}

TEST(AnalysisThreads, ShadowComparisonIsTheSerialOneBitForBit) {
  const AtriumFrame& f = atriumFrame();
  auto compare = [&] {
    return compareShadows(f.scene, f.bvh, f.shadows, f.lists, f.kWidth, f.kHeight, f.kTileSize, true);
  };
  const ShadowComparison serial = onThreads(1, compare);
  for (unsigned threads : kThreadCounts) {
    const ShadowComparison c = onThreads(threads, compare);
    EXPECT_EQ(c.visibility, serial.visibility) << threads << " threads";
    EXPECT_EQ(c.pairs, serial.pairs);
    EXPECT_EQ(c.rays, serial.rays);
    EXPECT_EQ(c.mismatches, serial.mismatches);
    EXPECT_EQ(c.nearTie, serial.nearTie);
    EXPECT_EQ(c.endpoint, serial.endpoint);
    EXPECT_EQ(c.grazing, serial.grazing);
  }
}

}  // namespace
}  // namespace hb
