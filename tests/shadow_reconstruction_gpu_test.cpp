// The shadow pass's reconstructed normals and world positions on the real device (lavapipe on CI),
// against their derived float bounds and the double-precision reference surface.
#include <cmath>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "shadows_gpu_common.h"

namespace hb {
namespace {

using namespace shadowtest;

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

}  // namespace
}  // namespace hb
