// The shadow pass on the real device (lavapipe on CI): both ray-tracing backends agree bit for bit,
// our own BVH traversal in compute (backend=compute) differs from them only where one of them
// differs from the double-precision CPU ray within its derived float bound,
// the ray accounting adds up, normals and world positions meet their float bounds, and the
// visibility agrees with a double-precision CPU shadow ray from the GPU's own positions.
#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "analysis/ray_analysis.h"
#include "base/numbers.h"
#include "effects/shadows/shadows_part.h"
#include "frame/renderer.h"
#include "gpu/gpu_lights.h"
#include "gpu/trace_bvh.h"
#include "gpu_fixture.h"
#include "scene/hard_cases.h"
#include "shadow_frame.h"
#include "shared/gpu_types.h"

namespace hb {
namespace {

constexpr uint32_t kWidth = 320, kHeight = 180;
constexpr NormalCulling kNormalModes[] = {NormalCulling::Off, NormalCulling::Naive, NormalCulling::Improved};

struct ShadowFrame : hb::testing::ShadowedFrame {
  ReconstructionCamera<double> cam;
  size_t pixels() const { return depth.size(); }
};

ShadowFrame render(const VulkanContext& ctx, const Scene& scene, NormalCulling normals, const std::string& backend,
                   uint32_t tileSize = 16, bool scaledTMin = false, uint32_t bvhWidth = 2) {
  RenderSettings s{.width = kWidth,
                   .height = kHeight,
                   .tileSize = tileSize,
                   .backend = hb::testing::backendNamed(backend),
                   .bvhWidth = bvhWidth,
                   .normals = normals};
  s.tMin = scaledTMin ? ShadowTMin::Scaled : ShadowTMin::Constant;
  Renderer r(ctx, scene, s);
  EXPECT_EQ(toString(shadowsOf(r)->shadowPass().settings().backend), backend);
  r.renderFrame(true);
  ShadowFrame f{{s, r.readDepth(), r.readCulling(), shadowsOf(r)->readShadows(), r.view(), r.proj()}, {}};
  f.cam = reconstructionCamera<double>(glm::dmat4(f.view), glm::dmat4(f.proj), s.width, s.height);
  return f;
}

const Scene& sceneNamed(const std::string& name) {
  static std::map<std::string, Scene> cache;
  auto it = cache.find(name);
  if (it == cache.end()) it = cache.emplace(name, makeBuiltinScene(name)).first;
  return it->second;
}

RayAccounting account(const ShadowFrame& f, const Scene& scene) {
  return accountRays(f.shadows, f.culling, f.depth, f.settings.width, f.settings.height, f.settings.tileSize,
                     uint32_t(scene.lights.size()));
}

ShadowComparison compare(const ShadowFrame& f, const Scene& scene, const Bvh& bvh) {
  // The camera position and t_min scale exactly as the renderer uploads them.
  const glm::vec4 cameraPos =
      makeFrameConstants(f.view, f.proj, f.settings.width, f.settings.height, f.settings.tileSize, 0,
                         f.settings.tMin == ShadowTMin::Scaled ? gpu::kShadowTMinPerMetre : 0.0f)
          .cameraPos;
  return compareShadows(scene, bvh, f.shadows, f.culling, f.settings.width, f.settings.height, f.settings.tileSize,
                        f.settings.rangeTest, cameraPos);
}

// Sky pixels carry nothing; everything else is finite and has w = 1.
void expectCleanImages(const ShadowFrame& f, const std::string& what) {
  size_t bad = 0;
  for (size_t i = 0; i < f.pixels(); ++i) {
    const float* n = &f.shadows.normals[4 * i];
    const float* p = &f.shadows.positions[4 * i];
    bool ok = true;
    for (int k = 0; k < 4; ++k) ok = ok && std::isfinite(n[k]) && std::isfinite(p[k]);
    if (!(f.depth[i] > 0.0f))
      ok = ok && f.shadows.visibility[i] == 0u && f.shadows.accounting[4 * i] == 0u &&
           f.shadows.accounting[4 * i + 1] == 0u && f.shadows.accounting[4 * i + 2] == 0u && p[3] == 0.0f &&
           n[0] == 0.0f && n[1] == 0.0f && n[2] == 0.0f;
    else
      ok = ok && p[3] == 1.0f;
    bad += !ok;
  }
  EXPECT_EQ(bad, 0u) << what << ": pixels with NaN/Inf, a sky pixel with a mask/normal/position, or w != 1";
}

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

// ---- normals --------------------------------------------------------------------------------------

class ShadowNormals : public testing::GpuTest {};

// Bound on the angle between a normal reconstructed from depth and the true normal of a plane
// seen head-on (plane and depth-step: every triangle is parallel to the image plane).
//  - Each reconstructed position errs by ε_P · r (r = distance to the eye), ε_P = ε_depth + ε_pos:
//    ε_depth = 16 u: the rasterised depth's relative error (depth_prepass_test: 4 u + 4 u for
//    the clip z and w dot products, 1 u for the divide, ~3 u for the float barycentrics of the
//    largest |z_ndc| over the triangle, which on a plane parallel to the image equals the depth
//    everywhere; 12 u, rounded up to 16 u). A relative error δ in depth moves the point along its
//    ray by r · δ · depth / (depth + C) <= r · δ. ε_pos = 8 u: the issue's bound on Alg. 4.1 in
//    float (ShadowPositions below checks it on these scenes).
//  - A derivative is a difference of two positions: error <= 2 ε_P r. It is one pixel's footprint
//    on the plane, s = z · 2 tan(fov/2) / H (the plane is parallel to the image: the footprint is
//    the same along x and y and at every pixel; z = the plane's view depth).
//  - n = cross(dx, dy) with dx ⟂ dy: turning dx by α and dy by β turns n by <= α + β, so the
//    angle is <= 2 · 2 ε_P r / s (first order; ε² terms are ~1e-12).
double planeNormalBoundRad(double r, double viewDepth, const Camera& cam) {
  const double epsP = 16.0 * kU + 8.0 * kU;
  const double s = viewDepth * 2.0 * std::tan(double(cam.yfov) / 2.0) / kHeight;
  return 4.0 * epsP * r / s;
}

// Counts matched pixels whose reconstructed normal is further from +z than the plane bound.
size_t pixelsBeyondPlaneBound(const ShadowFrame& f, const Scene& scene, const ReferenceSurface& ref, double* maxRatio) {
  size_t beyond = 0;
  *maxRatio = 0;
  const glm::dvec3 eye = ref.eye;
  for (size_t i = 0; i < f.pixels(); ++i) {
    if (ref.state[i] != SurfaceState::Matched) continue;
    const glm::dvec3 n(f.shadows.normals[4 * i], f.shadows.normals[4 * i + 1], f.shadows.normals[4 * i + 2]);
    EXPECT_GT(glm::length(n), 0.0) << "pixel " << i << " has no normal";
    const double angle = std::atan2(glm::length(glm::cross(n, ref.normal[i])), glm::dot(n, ref.normal[i]));
    const double r = glm::length(ref.position[i] - eye);
    const double bound = planeNormalBoundRad(r, eye.z - ref.position[i].z, scene.cameras[0]);
    *maxRatio = std::max(*maxRatio, angle / bound);
    beyond += angle > bound;
  }
  return beyond;
}

TEST_F(ShadowNormals, ImprovedIsExactOnThePlaneToTheFloatBound) {
  const Scene& scene = sceneNamed("plane");
  const ShadowFrame f = render(*ctx, scene, NormalCulling::Improved, exactBackend());
  const ReferenceSurface ref = referenceSurface(buildBvh(scene), f.depth, f.cam);
  ASSERT_EQ(ref.unmatched, 0u);
  double ratio;
  EXPECT_EQ(pixelsBeyondPlaneBound(f, scene, ref, &ratio), 0u);
  std::printf("[ normals ] plane improved: max angle / bound = %.3g\n", ratio);
}

TEST_F(ShadowNormals, ImprovedKeepsEachSideOfTheDepthStep) {
  const Scene& scene = sceneNamed("depth-step");
  const Bvh bvh = buildBvh(scene);
  const ShadowFrame improved = render(*ctx, scene, NormalCulling::Improved, exactBackend());
  const ReferenceSurface ref = referenceSurface(bvh, improved.depth, improved.cam);
  ASSERT_EQ(ref.unmatched, 0u);
  double ratio;
  EXPECT_EQ(pixelsBeyondPlaneBound(improved, scene, ref, &ratio), 0u) << "improved normals mixed the two sides";
  // The scene does test something: naive normals take the derivative across the step there.
  const ShadowFrame naive = render(*ctx, scene, NormalCulling::Naive, exactBackend());
  const NormalAccuracy acc = normalAccuracy(naive.shadows.normals, ref);
  EXPECT_GT(acc.maxAngleDeg, 45.0);
  std::printf("[ normals ] depth-step improved: max angle / bound = %.3g; naive max %.1f deg\n", ratio,
              acc.maxAngleDeg);
}

TEST_F(ShadowNormals, ImprovedHasALowerMeanErrorThanNaiveOnTheAtrium) {
  const Scene& scene = sceneNamed("atrium");
  const Bvh bvh = buildBvh(scene);
  const ShadowFrame naive = render(*ctx, scene, NormalCulling::Naive, exactBackend());
  const ShadowFrame improved = render(*ctx, scene, NormalCulling::Improved, exactBackend());
  const ReferenceSurface ref = referenceSurface(bvh, naive.depth, naive.cam);
  const NormalAccuracy a = normalAccuracy(naive.shadows.normals, ref);
  const NormalAccuracy b = normalAccuracy(improved.shadows.normals, ref);
  EXPECT_LT(b.meanAngleDeg, a.meanAngleDeg);
  EXPECT_LT(b.meanImageDifference, a.meanImageDifference);
  EXPECT_EQ(a.compared, b.compared);
  // Reference surface found for all but a few silhouette pixels.
  EXPECT_LT(ref.unmatched, ref.matched / 1000);
  std::printf(
      "[ normals ] atrium %ux%u: naive mean %.3f p95 %.3f max %.1f deg, image diff %.5f | improved mean "
      "%.3f p95 %.3f max %.1f deg, image diff %.5f | unmatched %llu of %llu\n",
      kWidth, kHeight, a.meanAngleDeg, a.p95AngleDeg, a.maxAngleDeg, a.meanImageDifference, b.meanAngleDeg,
      b.p95AngleDeg, b.maxAngleDeg, b.meanImageDifference, (unsigned long long)ref.unmatched,
      (unsigned long long)(ref.matched + ref.unmatched));
}

// The issue's target, at the thesis's resolution: the improved method's mean normal error at most
// 0.28 x the naive one's (the thesis's image-difference ratio is 0.02264 / 0.07975 = 0.284). The
// ratio depends on the resolution (at 320x180 far more pixels lie next to a depth edge: 0.57 above)
// and hardly on the device (H100 0.279, lavapipe 0.278 at 1920x1080). A target, not a derived
// tolerance: the test fails if either method's quality changes.
TEST_F(ShadowNormals, ImprovedMeanAngularErrorIsAtMost028OfNaiveOnTheAtriumAt1080p) {
  const Scene& scene = sceneNamed("atrium");
  const Bvh bvh = buildBvh(scene);
  NormalAccuracy acc[2];
  ReferenceSurface ref;
  for (int k = 0; k < 2; ++k) {
    RenderSettings s;
    s.width = 1920;
    s.height = 1080;
    s.tileSize = 8;
    s.normals = k == 0 ? NormalCulling::Naive : NormalCulling::Improved;
    Renderer r(*ctx, scene, s);
    r.renderFrame(true);
    if (k == 0)
      ref =
          referenceSurface(bvh, r.readDepth(),
                           reconstructionCamera<double>(glm::dmat4(r.view()), glm::dmat4(r.proj()), s.width, s.height));
    acc[k] = normalAccuracy(shadowsOf(r)->readShadows().normals, ref);
  }
  const double ratio = acc[1].meanAngleDeg / acc[0].meanAngleDeg;
  std::printf(
      "[ normals ] atrium 1920x1080: naive mean %.3f deg, image diff %.5f | improved mean %.3f deg, image diff "
      "%.5f | ratio %.3f (image %.3f)\n",
      acc[0].meanAngleDeg, acc[0].meanImageDifference, acc[1].meanAngleDeg, acc[1].meanImageDifference, ratio,
      acc[1].meanImageDifference / acc[0].meanImageDifference);
  EXPECT_EQ(acc[0].compared, acc[1].compared);
  EXPECT_LE(ratio, 0.28);
}

// ---- world positions ----------------------------------------------------------------------------

class ShadowPositions : public testing::GpuTest {};

// One non-sky pixel's world position: cpu = Alg. 4.1 in double from its depth, gpu = the shadow
// pass's own.
struct PositionSample {
  uint32_t x, y;
  glm::dvec3 cpu, gpu;
};
std::vector<PositionSample> positionSamples(const ShadowFrame& f) {
  std::vector<PositionSample> samples;
  for (uint32_t y = 0; y < kHeight; ++y)
    for (uint32_t x = 0; x < kWidth; ++x) {
      const size_t i = size_t(y) * kWidth + x;
      if (!(f.depth[i] > 0.0f)) continue;
      const float* p = &f.shadows.positions[4 * i];
      samples.push_back({x, y, worldFromDepth<double>(f.cam, x, y, double(f.depth[i])), glm::dvec3(p[0], p[1], p[2])});
    }
  return samples;
}

// The issue's bound: Alg. 4.1 in float within 4 · 2^-23 · distance of the double reconstruction
// from the same depth value. It assumes the eye near the world origin: the view-space point has
// relative error a few u (ndc, /A, (depth + C)/D, /w), and the final viewInv · v adds rounding
// relative to the magnitudes it sums, which are ~distance when |eye| <~ distance. Every scene but
// far-origin satisfies that; measured max 0.54 of the bound (atrium).
TEST_F(ShadowPositions, Alg41IsWithinFourUlpsOfTheDistanceNearTheOrigin) {
  for (const std::string& name : builtinSceneNames()) {
    if (name == "far-origin") continue;
    const ShadowFrame f = render(*ctx, sceneNamed(name), NormalCulling::Off, exactBackend());
    const PositionAccuracy acc = positionAccuracy(f.shadows.positions, f.depth, f.cam);
    EXPECT_EQ(acc.nonFinite, 0u) << name;
    EXPECT_LE(acc.maxRelative, 8.0 * kU) << name;
    std::printf("[ positions ] %-14s max %.3g (%.2f of 4*2^-23) mean %.3g; vs plain double %.3g\n", name.c_str(),
                acc.maxRelative, acc.maxRelative / (8.0 * kU), acc.meanRelative, acc.maxRelativePlain);
  }
}

// The issue's distances one by one: far-planes puts a plane at 0.1 m, 100 m and 900 m in thirds of
// the image (camera at the origin, znear 0.05, zfar 1000: reverse-Z keeps float depth precision
// roughly constant relative to distance). Each plane's pixels, told apart by their reconstructed
// distance, stay within the same 4·2^-23·distance bound (derivation above), and each plane has
// its own figure, so that a precision loss at one distance cannot hide in the others' average.
TEST_F(ShadowPositions, EachFarPlaneKeepsItsPositionsWithinFourUlpsOfItsDistance) {
  const ShadowFrame f = render(*ctx, sceneNamed("far-planes"), NormalCulling::Off, exactBackend());
  struct PlaneFigure {
    size_t pixels = 0;
    double maxRel = 0, sumRel = 0;
  } planes[3];
  for (const PositionSample& s : positionSamples(f)) {
    const double dist = -s.cpu.z;  // view = world here, the planes face +z
    int k = 0;
    while (k < 2 && std::abs(dist - kFarPlaneDepths[k]) > 0.01 * kFarPlaneDepths[k]) ++k;
    ASSERT_LT(std::abs(dist - kFarPlaneDepths[k]), 0.01 * kFarPlaneDepths[k]) << "pixel " << s.x << "," << s.y;
    const double rel = glm::length(s.gpu - s.cpu) / glm::length(s.cpu);
    planes[k].pixels++;
    planes[k].maxRel = std::max(planes[k].maxRel, rel);
    planes[k].sumRel += rel;
  }
  for (int k = 0; k < 3; ++k) {
    // Each plane fills about a third of the image (320x180 / 3 = 19,200 px, overhang included).
    EXPECT_GT(planes[k].pixels, kWidth * kHeight / 4) << kFarPlaneDepths[k] << " m";
    EXPECT_LE(planes[k].maxRel, 8.0 * kU) << kFarPlaneDepths[k] << " m";
    std::printf("[ positions ] far-planes at %5.1f m: %zu px, max relative %.3g (%.2f of 4*2^-23), mean %.3g\n",
                kFarPlaneDepths[k], planes[k].pixels, planes[k].maxRel, planes[k].maxRel / (8.0 * kU),
                planes[k].sumRel / double(planes[k].pixels));
  }
}

// Far from the origin the bound relative to distance cannot hold: world = viewInv · v sums terms
// of size |eye| (10 km here) whose float rounding is ~u |eye| ≈ 0.6 mm, and viewInv itself is
// inverted in float (makeFrameConstants: glm::inverse of a float matrix), which misplaces the
// translation by a few ulps of |eye|. The bound that holds, term by term:
//   |p_gpu − p_cpu| <= 8 u · d                      (Alg. 4.1 up to the view-space point, as above)
//                    + |(Mf − Md) · (v, 1)|          (the float inverse's error, computed exactly
//                                                     from the two matrices: no tolerance)
//                    + 3 u · (√3 d + |t|) · √3        (rounding of the 3 products and 3 sums per
//                                                     component of Mf · (v, 1), |R| = 1, t = eye)
// where v is the view-space point, d = |v| and Md = inverse in double.
TEST_F(ShadowPositions, FarFromTheOriginTheErrorFollowsTheEyeDistanceBound) {
  const Scene& scene = sceneNamed("far-origin");
  const ShadowFrame f = render(*ctx, scene, NormalCulling::Off, exactBackend());
  const glm::dmat4 mf(glm::inverse(f.view));  // what makeFrameConstants uploads
  const glm::dmat4 md = glm::inverse(glm::dmat4(f.view));
  const glm::dvec3 t(md[3]);
  size_t beyond = 0, compared = 0, beyondIssue = 0;
  double maxRatio = 0, maxRel = 0;
  for (const PositionSample& s : positionSamples(f)) {
    const glm::dvec4 v = glm::dmat4(f.view) * glm::dvec4(s.cpu, 1.0);
    const double d = glm::length(glm::dvec3(v));
    const double bound = 8.0 * kU * d + glm::length(glm::dvec3((mf - md) * v)) +
                         3.0 * kU * (std::sqrt(3.0) * d + glm::length(t)) * std::sqrt(3.0);
    const double err = glm::length(s.gpu - s.cpu);
    beyond += err > bound;
    beyondIssue += err > 8.0 * kU * d;
    maxRatio = std::max(maxRatio, err / bound);
    maxRel = std::max(maxRel, err / d);
    compared++;
  }
  ASSERT_GT(compared, 1000u);
  EXPECT_EQ(beyond, 0u);
  std::printf(
      "[ positions ] far-origin: max relative %.3g (%.0f x 4*2^-23; %zu of %zu pixels beyond it); "
      "max error / derived bound %.2f; float-inverse translation error %.3g m\n",
      maxRel, maxRel / (8.0 * kU), beyondIssue, compared, maxRatio, glm::length(glm::dvec3(mf[3] - md[3])));
}

// ---- hard cases -----------------------------------------------------------------------------------

class ShadowHardCases : public testing::GpuTest {};

// Under the box the shadow ray meets the underside after t = gap / sin(elevation) (1.04 mm here):
// just beyond t_min = 1 mm, so the 1 mm occluder still shadows. CPU BVH, the receiver's points
// under the box (the camera cannot see them: the box is in front).
TEST_F(ShadowHardCases, ThinGapOccluderShadowsTheReceiverUnderIt) {
  const Scene& scene = sceneNamed("thin-gap");
  const Bvh bvh = buildBvh(scene);
  const glm::dvec3 light(scene.lights[0].position);
  int occluded = 0, total = 0;
  for (double x = -0.19; x <= 0.19; x += 0.02)
    for (double z = -0.19; z <= 0.19; z += 0.02) {
      const glm::dvec3 p(x, 0.0, z), dir = glm::normalize(light - p);
      double t;
      uint32_t tri;
      total++;
      if (!bvh.closestHit(p, dir, gpu::kShadowTMin, glm::length(light - p), t, tri)) continue;
      // The underside lies at float(kThinGap) (vertex positions are float); t = height / dir.y,
      // computed in double to a few eps of t.
      EXPECT_NEAR(t, double(float(kThinGap)) / dir.y, 1e-15) << "the first hit is the box's underside";
      occluded++;
    }
  EXPECT_EQ(occluded, total);
}

// The same scene with the light lowered to 5.7 degrees so that the box's shadow reaches out from
// under it where the camera sees it; receiver points within ~1.5 cm of the box send their shadow
// ray into the 1 mm gap, where it ends on the underside. The GPU shadows them.
TEST_F(ShadowHardCases, ThinGapRaysThatEnterTheGapEndOnTheUnderside) {
  Scene scene = sceneNamed("thin-gap");
  scene.lights[0].position = {1.5f, 0.15f, 0.0f};
  const Bvh tbvh = buildBvh(scene);
  const ShadowFrame f = render(*ctx, scene, NormalCulling::Improved, exactBackend());
  const ShadowComparison cmp = compare(f, scene, buildBvh(scene));
  EXPECT_EQ(cmp.unexplained(), 0u);
  const glm::dvec3 light(scene.lights[0].position);
  int shadowed = 0, underside = 0;
  for (size_t i = 0; i < f.pixels(); ++i) {
    const glm::dvec3 p(f.shadows.positions[4 * i], f.shadows.positions[4 * i + 1], f.shadows.positions[4 * i + 2]);
    if (f.shadows.positions[4 * i + 3] != 1.0f || std::abs(p.y) > 1e-5 || std::abs(p.x) <= 0.2) continue;
    double t;
    uint32_t tri;
    const glm::dvec3 dir = glm::normalize(light - p);
    if (!tbvh.closestHit(p, dir, gpu::kShadowTMin, glm::length(light - p), t, tri)) continue;
    EXPECT_EQ(f.shadows.visibility[i] & 1u, 0u) << "receiver pixel " << i << " is lit under the box";
    shadowed++;
    underside += std::abs((p + t * dir).y - double(float(kThinGap))) < 1e-9;  // hit on the underside plane
  }
  EXPECT_GT(shadowed, 20);
  EXPECT_GT(underside, 0) << "no visible pixel sends its ray into the gap: the test lost its point";
  std::printf("[ hard cases ] thin-gap (light lowered): %d shadowed receiver pixels, %d of them through the gap\n",
              shadowed, underside);
}

// The camera sees the quad's back and the ground behind it; shadow rays from there hit the quad
// from behind (its back face: single quad, no closed volume) and must count as hits.
TEST_F(ShadowHardCases, OpenOccluderShadowsFromBehind) {
  const Scene& scene = sceneNamed("open-occluder");
  for (const char* backend : {"rayquery", "pipeline", "compute"}) {
    if (std::string(backend) == "rayquery" && !ctx->info().rayQuery) continue;  // every tracer the device has
    if (std::string(backend) == "pipeline" && !ctx->info().rayTracingPipeline) continue;
    const ShadowFrame f = render(*ctx, scene, NormalCulling::Improved, backend);
    const glm::dvec3 light(scene.lights[0].position);
    int inShadow = 0;
    double groundY = 0.0;  // the largest |y| of the ground points counted
    for (size_t i = 0; i < f.pixels(); ++i) {
      const glm::dvec3 p(f.shadows.positions[4 * i], f.shadows.positions[4 * i + 1], f.shadows.positions[4 * i + 2]);
      // The ground's points: the scene's only other surface, the quad, lies at y >= 0.5, so a point
      // within 0.25 of y = 0 is the ground's whatever the depth's rounding. (A 1e-5 cut took no
      // pixel at all on an NVIDIA H200, whose raster hardware puts the ground's reconstructed
      // points further from y = 0 than lavapipe.)
      if (f.shadows.positions[4 * i + 3] != 1.0f || std::abs(p.y) > 0.25) continue;
      // Where the segment to the light crosses z = 0 inside the quad (|x| < 1, 0.5 < y < 1.5),
      // with a 5 cm margin from its edges.
      if (p.z >= 0.0) continue;
      const double s = -p.z / (light.z - p.z);
      const glm::dvec3 q = p + s * (light - p);
      if (std::abs(q.x) > 0.95 || q.y < 0.55 || q.y > 1.45) continue;
      EXPECT_EQ(f.shadows.visibility[i] & 1u, 0u) << backend << ": ground pixel " << i << " behind the quad is lit";
      inShadow++;
      groundY = std::max(groundY, std::abs(p.y));
    }
    EXPECT_GT(inShadow, 100) << backend;
    std::printf(
        "[ hard cases ] open-occluder %s: %d ground pixels behind the quad, all in shadow; largest |y| %.3g m\n",
        backend, inShadow, groundY);
  }
}

// A ray that enters the closed cube exactly through a shared edge, a vertex or a face's diagonal
// (the face centre) hits it: no ray slips through the crack between the triangles that share it
// (watertight). The camera cannot aim a pixel's shadow ray exactly at an edge, so this is checked
// on the CPU BVH, the same one the GPU's visibility is held to above
// (ShadowScenes/ShadowBackends.*/cube, where every rasterised pixel agreed).
// Construction: every coordinate is a small dyadic rational, so dir = target - origin is exact and
// the ray passes exactly through the target. origin = target + 1/8 · (1 n1 + 2 n2 + 3 n3) over
// the outward normals of the faces meeting there (a face centre gets a dyadic tilt instead of
// n2, n3), so the ray enters through all of them (d · n_i < 0: not a silhouette, where touching is
// legitimately ambiguous). It stops 2^-20 past the target: inside the cube but far from any other
// face, so a hit can only come from the triangles at the target.
TEST_F(ShadowHardCases, CubeEdgesVerticesAndDiagonalsBlockRaysEnteringThroughThem) {
  const Bvh bvh = buildBvh(sceneNamed("cube"));
  int rays = 0;
  for (double cx : {-0.5, 0.0, 0.5})
    for (double cy : {0.5, 1.0, 1.5})
      for (double cz : {-0.5, 0.0, 0.5}) {
        std::vector<glm::dvec3> normals;
        if (std::abs(cx) == 0.5) normals.push_back({cx * 2, 0, 0});
        if (cy != 1.0) normals.push_back({0, cy == 1.5 ? 1 : -1, 0});
        if (std::abs(cz) == 0.5) normals.push_back({0, 0, cz * 2});
        if (normals.empty()) continue;  // the centre of the cube
        const glm::dvec3 target(cx, cy, cz);
        glm::dvec3 offset(0.0);
        for (size_t k = 0; k < normals.size(); ++k) offset += double(k + 1) * normals[k];
        if (normals.size() == 1) offset = 3.0 * normals[0] + glm::dvec3(0.75, 0.5, 0.25) * (1.0 - glm::abs(normals[0]));
        const glm::dvec3 origin = target + 0.125 * offset;
        const glm::dvec3 dir = target - origin;
        ASSERT_EQ(origin + dir, target);  // exact
        ASSERT_GT(origin.y, 0.0);         // above the ground: nothing else in the way
        for (const glm::dvec3& n : normals) ASSERT_LT(glm::dot(dir, n), 0.0);
        EXPECT_TRUE(bvh.occluded(origin, dir, gpu::kShadowTMin, 1.0 + 1.0 / 1048576.0))
            << "ray into (" << cx << "," << cy << "," << cz << ") from (" << origin.x << "," << origin.y << ","
            << origin.z << ")";
        rays++;
      }
  EXPECT_EQ(rays, 8 + 12 + 6);  // vertices, edge midpoints, face centres
}

}  // namespace
}  // namespace hb
