// The shadow pass on the real device (lavapipe on CI): both ray-tracing backends agree bit for bit,
// our own BVH traversal in compute (backend=compute) differs from them only where one of them
// differs from the double-precision CPU ray within its derived float bound, the ray accounting adds
// up, and the visibility agrees with a double-precision CPU shadow ray from the GPU's own positions.
#include <cmath>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "shadows_gpu_common.h"

namespace hb {
namespace {

using namespace shadowtest;

// Whether two frames traced the same rays at pixel i: the same position, normal and lights traced.
// Each backend reconstructs its rays' origins and normals in its own shader (a ray-generation shader,
// a compute shader); the NVIDIA driver compiles them to different roundings (on the H200, 2-64
// pixels of a built-in scene at 320x180 got a different position or normal from the pipeline than
// from compute, and every one of them was a differing mask: results/h200/raster3d-52/ceilings).
bool sameRays(const ShadowFrame& a, const ShadowFrame& b, size_t i) {
  for (int k = 0; k < 4; ++k)
    if (a.shadows.positions[4 * i + k] != b.shadows.positions[4 * i + k] ||
        a.shadows.normals[4 * i + k] != b.shadows.normals[4 * i + k])
      return false;
  return a.shadows.traced[i] == b.shadows.traced[i];
}

// Pixels whose masks differ, split into those that traced the same rays and those that did not.
struct MaskDiff {
  size_t sameRays = 0, otherRays = 0;
  std::string text() const {
    return std::to_string(sameRays) + " with the same rays, " + std::to_string(otherRays) +
           " with another position, normal or set of lights";
  }
};

// Non-sky pixels whose two reconstructed positions lie farther apart than rounding allows. Each is
// Alg. 4.1 in float from the same depth, within 8u of the magnitudes its last step sums, |eye| +
// distance (ShadowPositions' derivation, which bounds by the distance alone where |eye| <~
// distance), so the two lie within 16u·(|eye| + distance) of each other. A pixel that took a
// neighbour's position instead (a pixel's footprint, ~distance/300 at 320x180) is far outside.
size_t positionsApart(const ShadowFrame& a, const ShadowFrame& b) {
  const glm::dvec3 eye(a.cam.viewInv[3]);
  size_t apart = 0;
  for (size_t i = 0; i < a.pixels(); ++i) {
    if (!(a.depth[i] > 0.0f)) continue;
    const glm::dvec3 pa(a.shadows.positions[4 * i], a.shadows.positions[4 * i + 1], a.shadows.positions[4 * i + 2]);
    const glm::dvec3 pb(b.shadows.positions[4 * i], b.shadows.positions[4 * i + 1], b.shadows.positions[4 * i + 2]);
    apart += !(glm::length(pa - pb) <= 16.0 * kU * (glm::length(eye) + glm::length(pa - eye)));
  }
  return apart;
}

MaskDiff maskDiff(const ShadowFrame& a, const ShadowFrame& b) {
  MaskDiff d;
  for (size_t i = 0; i < a.pixels(); ++i)
    if (a.shadows.visibility[i] != b.shadows.visibility[i]) ++(sameRays(a, b, i) ? d.sameRays : d.otherRays);
  return d;
}

// ---- both backends, every scene, every normal mode ---------------------------------------------

class ShadowBackends : public testing::GpuTest, public ::testing::WithParamInterface<std::string> {};

// The reference is ray query, or on a device without it (an H200) the driver's pipeline
// (exactBackend): both trace the driver's own acceleration structure, and the comparison of the two
// runs where both exist.
TEST_P(ShadowBackends, AgreeAddUpAndMatchTheCpuShadowRays) {
  const Scene& scene = sceneNamed(GetParam());
  const Bvh bvh = buildBvh(scene);
  const Bvh tbvh = buildBvh(scene);
  const std::string reference = exactBackend();
  if (reference == "compute") GTEST_SKIP() << "the device has neither ray query nor the ray-tracing pipeline";
  const std::string second = ctx->info().rayTracingPipeline ? "pipeline" : reference;
  for (NormalCulling normals : kNormalModes) {
    const std::string what = GetParam() + " normals=" + toString(normals);
    const ShadowFrame rq = render(*ctx, scene, normals, reference);
    const ShadowFrame rt = render(*ctx, scene, normals, second);
    size_t visDiff = 0, accDiff = 0;
    for (size_t i = 0; i < rq.pixels(); ++i) {
      visDiff += rq.shadows.visibility[i] != rt.shadows.visibility[i];
      accDiff += rq.shadows.accounting[i] != rt.shadows.accounting[i];
    }
    EXPECT_EQ(visDiff, 0u) << what << ": pixels whose visibility mask differs between " << reference << " and "
                           << second;
    // backend=compute: our BVH and watertight test in float. A pixel whose mask differs from ray
    // query's although both traced the same rays (sameRays) holds a pair on which one of the two
    // differs from the double-precision CPU ray, and every such pair must be explained
    // (compareShadows' float bound), so those pixels are at most the two backends' mismatches
    // together. A pixel where the two reconstructed another position or normal traced other rays:
    // each frame's rays are held to the CPU's from its own positions (compare, below, for both).
    // The 4- and 8-wide trees (bvh_width=4, 8) test the same triangles with the same test: held to the
    // same.
    const ShadowFrame cp = render(*ctx, scene, normals, "compute");
    const ShadowFrame cp4 = render(*ctx, scene, normals, "compute", 16, false, 4);
    const ShadowFrame cp8 = render(*ctx, scene, normals, "compute", 16, false, 8);
    const MaskDiff cpDiff = maskDiff(rq, cp);
    size_t cp4Diff = 0, cp8Diff = 0;
    for (size_t i = 0; i < rq.pixels(); ++i) {
      cp4Diff += cp.shadows.visibility[i] != cp4.shadows.visibility[i];
      cp8Diff += cp.shadows.visibility[i] != cp8.shadows.visibility[i];
    }
    const ShadowComparison cmpCp = compare(cp, scene, bvh);
    EXPECT_EQ(cmpCp.unexplained(), 0u) << what << " compute: " << cmpCp.mismatches << " mismatches of " << cmpCp.pairs;
    EXPECT_TRUE(account(cp, scene).addsUp()) << what << " compute";
    expectCleanImages(cp, what + " compute");
    // Any hit is any hit: the same rays, triangles and watertight test give the same answer, whichever
    // box order found the hit.
    EXPECT_EQ(cp4Diff, 0u) << what << ": pixels whose mask differs between bvh_width 2 and 4";
    EXPECT_EQ(cp8Diff, 0u) << what << ": pixels whose mask differs between bvh_width 2 and 8";
    expectCleanImages(cp4, what + " compute, bvh_width 4");
    expectCleanImages(cp8, what + " compute, bvh_width 8");
    EXPECT_EQ(accDiff, 0u) << what << ": pixels whose accounting differs between " << reference << " and " << second;
    expectCleanImages(rq, what + " rayquery");
    expectCleanImages(rt, what + " pipeline");

    const RayAccounting acc = account(rq, scene);
    EXPECT_TRUE(acc.addsUp()) << what << ": " << acc.candidates << " candidates, buckets sum to " << acc.bucketSum();
    EXPECT_TRUE(account(rt, scene).addsUp()) << what;
    EXPECT_EQ(acc.culledByRange, 0u) << what << ": range test is off";
    if (normals == NormalCulling::Off) {
      // Nothing between the tile list and the ray but lights at the point and non-casters.
      EXPECT_EQ(acc.culledByNormal, 0u) << what;
      EXPECT_EQ(acc.traced, acc.candidates - acc.culledByTile - acc.droppedByOverflow - acc.atLight - acc.noShadow)
          << what;
      // Without normal culling and without overflow the tile list holds every light the oracle
      // needs (culling is conservative), so no pixel traces fewer rays than the oracle.
      if (acc.droppedByOverflow == 0) {
        const OracleRays oracle = oracleRays(scene, referenceSurface(tbvh, rq.depth, rq.cam));
        size_t below = 0;
        for (size_t i = 0; i < rq.pixels(); ++i) below += oracle.perPixel[i] > acc.perPixel[i];
        EXPECT_EQ(below, 0u) << what << ": pixels that traced fewer rays than the oracle";
        EXPECT_LE(oracle.total, acc.traced) << what;
      }
    }

    // Visibility against the CPU's double-precision BVH from the GPU's own positions and normals.
    // Mismatches are allowed only where float rounding may decide either way (ray_analysis.h
    // compareShadows: ties of N.L, hits at the ray's ends, rays grazing an edge, each judged by a
    // perturbation of 2^-17 of the magnitudes involved); none may be left unexplained.
    const ShadowComparison cmp = compare(rq, scene, bvh);
    EXPECT_EQ(cmp.unexplained(), 0u) << what << ": " << cmp.mismatches << " mismatches of " << cmp.pairs << " pairs";
    EXPECT_EQ(positionsApart(rq, cp), 0u)
        << what << ": pixels whose compute position is not " << reference << "'s within rounding";
    EXPECT_LE(cpDiff.sameRays, cmp.mismatches + cmpCp.mismatches)
        << what << ": pixels whose mask differs, compute against " << reference << " (" << cpDiff.text() << ")";
    // Not a tolerance but a check that the explanation stays meaningful: if a large share of the
    // rays needed it, δ would be hiding real errors. lavapipe measured 0 on every scene but
    // grazing-far, which exists to make the thesis's constant t_min fail: a third of its rays
    // start below the plane and hit it within a few cm, where float and double may disagree on
    // every one of them (lavapipe: 2,961 of 47,140, all explained). ShadowScaledTMin holds that
    // scene to the same 1/1000 with the remedy.
    if (GetParam() != "grazing-far") {
      EXPECT_LE(cmp.mismatches, cmp.rays / 1000) << what;
    }
    std::printf(
        "[ shadows ] %-14s normals=%s traced %llu of %llu candidates, CPU mismatches %llu "
        "(tie %llu, endpoint %llu, grazing %llu); compute: CPU mismatches %llu, pixels differing from %s: "
        "%zu with the same rays, %zu with others\n",
        GetParam().c_str(), toString(normals), (unsigned long long)acc.traced, (unsigned long long)acc.candidates,
        (unsigned long long)cmp.mismatches, (unsigned long long)cmp.nearTie, (unsigned long long)cmp.endpoint,
        (unsigned long long)cmp.grazing, (unsigned long long)cmpCp.mismatches, reference.c_str(), cpDiff.sameRays,
        cpDiff.otherRays);
  }
}

INSTANTIATE_TEST_SUITE_P(ShadowScenes, ShadowBackends, ::testing::ValuesIn(builtinSceneNames()),
                         [](const ::testing::TestParamInfo<std::string>& param) {
                           std::string n = param.param;
                           for (char& c : n)
                             if (c == '-') c = '_';
                           return n;
                         });

// backend=compute at every tile size: a tile's workgroup keeps its traversal stacks in shared memory
// only where they fit (trace_bvh.h traceStackShared: 8 KiB). The atrium's reinserted binary tree
// needs 33 entries, 8.25 KiB at 64 threads, so its stacks are in local memory at every tile size;
// a built-in scene whose stack fits at 8x8 tests the shared form. Both forms give ray query's
// visibility (the 1024-thread workgroup's stacks in shared memory once lost the H200 device).
class ShadowComputeTiles : public testing::GpuTest {};

TEST_F(ShadowComputeTiles, ComputeBackendAtEveryTileSizeEqualsRayQuery) {
  // Ray query's visibility, or the driver's pipeline's where there is no ray query (exactBackend).
  // Equal on every pixel that traced the same rays (sameRays); where the two shaders reconstructed
  // another position or normal, both frames' pairs are held to the CPU's double-precision rays from
  // their own positions, every mismatch explained (as in ShadowBackends).
  const std::string reference = exactBackend();
  if (reference == "compute") GTEST_SKIP() << "the device has neither ray query nor the ray-tracing pipeline";
  const Bvh cpuBvh = buildBvh(sceneNamed("atrium"));
  const auto expectEqual = [&](const ShadowFrame& rq, const ShadowFrame& cp, const Scene& scene, const Bvh& bvh,
                               const std::string& what) {
    const MaskDiff d = maskDiff(rq, cp);
    EXPECT_EQ(d.sameRays, 0u) << what << ": pixels whose mask differs from " << reference << "'s (" << d.text() << ")";
    EXPECT_EQ(positionsApart(rq, cp), 0u)
        << what << ": pixels whose compute position is not " << reference << "'s within rounding";
    if (d.otherRays == 0) return;
    EXPECT_EQ(compare(rq, scene, bvh).unexplained(), 0u) << what << ": " << reference;
    EXPECT_EQ(compare(cp, scene, bvh).unexplained(), 0u) << what << ": compute";
  };
  const Scene& scene = sceneNamed("atrium");
  for (uint32_t tile : {8u, 16u, 32u}) {
    const ShadowFrame rq = render(*ctx, scene, NormalCulling::Improved, reference, tile);
    const ShadowFrame cp = render(*ctx, scene, NormalCulling::Improved, "compute", tile);
    const TraceBvh bvh = buildTraceBvh(*ctx, scene);
    EXPECT_EQ(bvh.stack, bvh.depth - 1);
    EXPECT_EQ(traceStackShared(bvh, tile * tile), uint64_t(bvh.stack) * tile * tile * 4 <= 8192) << "tile " << tile;
    expectEqual(rq, cp, scene, cpuBvh, "tile " + std::to_string(tile));
    if (tile == 8)  // the wide trees' W − 1 entries a level: in local memory at 64 threads
      for (uint32_t width : {4u, 8u}) {
        const ShadowFrame cpw = render(*ctx, scene, NormalCulling::Improved, "compute", tile, false, width);
        const TraceBvh wide = buildTraceBvh(*ctx, scene, width);
        EXPECT_EQ(wide.stack, (width - 1) * wide.depth);
        EXPECT_LT(wide.depth, bvh.depth);
        expectEqual(rq, cpw, scene, cpuBvh, "bvh_width " + std::to_string(width));
      }
  }
  // The shared form: the first built-in scene whose binary stack fits at 8x8.
  bool sharedTested = false;
  for (const std::string& name : builtinSceneNames()) {
    const Scene& small = sceneNamed(name);
    if (name == "atrium" || !traceStackShared(buildTraceBvh(*ctx, small), 64)) continue;
    const ShadowFrame rq = render(*ctx, small, NormalCulling::Improved, reference, 8);
    const ShadowFrame cp = render(*ctx, small, NormalCulling::Improved, "compute", 8);
    expectEqual(rq, cp, small, buildBvh(small), name + " (stacks in shared memory)");
    sharedTested = true;
    break;
  }
  EXPECT_TRUE(sharedTested) << "no built-in scene keeps its stacks in shared memory at 8x8";
}

// ---- scaled t_min (beyond the thesis) --------------------------------------------------------------

// With t_min = max(0.001 m, 400u·|P − eye|) (gpu_types.h kShadowTMinPerMetre) both backends still
// agree bit for bit, and the CPU's double-precision rays from the GPU's positions with the same
// per-pixel t_min explain every difference, as in ShadowBackends: on the scenes where t_min grows
// (grazing up to ~140 m away, grazing-far 433-1100 m, far-planes at 100 m and 900 m) and where a larger t_min could
// wrongly light (thin-gap, a 1 mm gap; within 41.9 m of the eye t_min stays 1 mm).
class ShadowScaledTMin : public testing::GpuTest {};

TEST_F(ShadowScaledTMin, BackendsAgreeAndMatchTheCpuRaysWithTheSameTMin) {
  // Ray query against the pipeline where both exist; else the one there is (exactBackend) alone.
  const std::string reference = exactBackend();
  if (reference == "compute") GTEST_SKIP() << "the device has neither ray query nor the ray-tracing pipeline";
  const std::string other = ctx->info().rayTracingPipeline ? "pipeline" : reference;
  for (const char* name : {"grazing", "grazing-far", "far-planes", "far-origin", "thin-gap"}) {
    const Scene& scene = sceneNamed(name);
    const Bvh bvh = buildBvh(scene);
    const ShadowFrame rq = render(*ctx, scene, NormalCulling::Improved, reference, 16, /*scaledTMin=*/true);
    const ShadowFrame rt = render(*ctx, scene, NormalCulling::Improved, other, 16, /*scaledTMin=*/true);
    size_t visDiff = 0;
    for (size_t i = 0; i < rq.pixels(); ++i) visDiff += rq.shadows.visibility[i] != rt.shadows.visibility[i];
    EXPECT_EQ(visDiff, 0u) << name << ": pixels whose visibility mask differs between " << reference << " and "
                           << other;
    expectCleanImages(rq, std::string(name) + " scaled t_min");
    const ShadowComparison cmp = compare(rq, scene, bvh);
    EXPECT_EQ(cmp.unexplained(), 0u) << name << ": " << cmp.mismatches << " mismatches of " << cmp.pairs << " pairs";
    EXPECT_LE(cmp.mismatches, cmp.rays / 1000) << name;
    std::printf("[ t_min   ] %-14s scaled: CPU mismatches %llu of %llu rays\n", name,
                (unsigned long long)cmp.mismatches, (unsigned long long)cmp.rays);
  }
}

}  // namespace
}  // namespace hb
