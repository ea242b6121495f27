// Hard case: a light at grazing incidence (N·L = 0.01) on a large plane. A shadow ray leaves the
// reconstructed point at a slope of 0.01, so after t_min = 0.001 it has risen 1e-5 m; a point that
// depth reconstruction placed more than that below the plane hits the plane itself ("shadow acne").
// The reconstruction error grows with distance (about |P − eye|·4u, u = 2^-24: 1e-5 m at ~40 m),
// so the thesis's constant t_min may fail far away. The tests measure where, assert that near the
// camera, where the error bound stays below the ray's rise, there is none, and that the scaled
// t_min (beyond the thesis) has none at any distance.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "effects/shadows/shadows_part.h"
#include "frame/renderer.h"
#include "gpu_fixture.h"
#include "scene/hard_cases.h"
#include "shared/gpu_types.h"

namespace hb {
namespace {

class ShadowGrazing : public testing::GpuTest {
 protected:
  struct Acne {
    uint64_t nearPixels = 0, nearAcne = 0, farPixels = 0, farAcne = 0;
    uint64_t steepPixels = 0, steepAcne = 0;  // pixels where N·L >= 0.01 (any distance)
    double maxDistance = 0;
    // Signed distance of the GPU positions to the plane through vertex 0 (itself rounded to float,
    // so a diagnostic, not a test): below zero the ray may start under the surface.
    double minHeight = 1e30, maxHeight = -1e30;
  };

  // Renders a grazing scene (normal culling off: every lit pixel traces its ray, so acne is the
  // only way to be dark; nothing in the scene occludes the plane) and counts the dark pixels
  // within and beyond safeDistance of the eye.
  Acne measure(bool scaledTMin, const std::string& sceneName = "grazing", glm::dvec3 normal = {0, 1, 0}) {
    Scene scene = makeBuiltinScene(sceneName);
    RenderSettings s;
    s.width = 320;
    s.height = 180;
    s.tileSize = 16;
    s.normals = NormalCulling::Off;
    s.tMin = scaledTMin ? ShadowTMin::Scaled : ShadowTMin::Constant;
    Renderer renderer(*ctx, scene, s);
    renderer.renderFrame(true);
    const ShadowReadback sh = shadowsOf(renderer)->readShadows();
    const std::vector<float> depth = renderer.readDepth();
    const glm::dvec3 eye(glm::inverse(glm::dmat4(scene.cameras[0].view))[3]);
    const glm::dvec3 light(scene.lights[0].position);
    const double planeOffset = glm::dot(glm::dvec3(scene.vertices[0].position), normal);
    Acne a;
    for (size_t i = 0; i < depth.size(); ++i) {
      if (!(depth[i] > 0.0f)) continue;
      const uint32_t traced = sh.accounting[4 * i] & gpu::kAccountMask;
      if (traced == 0) continue;  // the light is not in this pixel's tile list (out of range)
      const glm::dvec3 p(sh.positions[i * 4], sh.positions[i * 4 + 1], sh.positions[i * 4 + 2]);
      const double d = glm::length(p - eye);
      const double nDotL = glm::dot(glm::normalize(light - p), normal);
      const bool dark = (sh.visibility[i] & 1u) == 0;
      (d < safeDistance ? a.nearPixels : a.farPixels)++;
      (d < safeDistance ? a.nearAcne : a.farAcne) += dark;
      if (nDotL >= 0.01) a.steepPixels++, a.steepAcne += dark;
      a.maxDistance = std::max(a.maxDistance, d);
      const double height = glm::dot(p, normal) - planeOffset;
      a.minHeight = std::min(a.minHeight, height);
      a.maxHeight = std::max(a.maxHeight, height);
    }
    std::printf(
        "%s, %s t_min: %llu/%llu acne pixels within %.1f m of the eye, %llu/%llu beyond (to %.0f m); "
        "%llu/%llu where N.L >= 0.01; heights %.3g..%.3g m\n",
        sceneName.c_str(), scaledTMin ? "scaled" : "constant", (unsigned long long)a.nearAcne,
        (unsigned long long)a.nearPixels, safeDistance, (unsigned long long)a.farAcne, (unsigned long long)a.farPixels,
        a.maxDistance, (unsigned long long)a.steepAcne, (unsigned long long)a.steepPixels, a.minHeight, a.maxHeight);
    return a;
  }

  // Rise of the ray at t_min = 0.001 m: 0.001 · 0.01 = 1e-5 m. Reconstruction error bound: 4u per
  // unit of distance to the eye (Alg. 4.1, tested in shadows_gpu_test) => safe while 4u·d < 1e-5,
  // i.e. d < 1e-5 / (4 · 2^-24) ≈ 41.9 m.
  const double safeDistance = 1e-5 / (4.0 * std::ldexp(1.0, -24));
};

// The thesis's constant t_min: no acne where the bound says it cannot occur. Beyond safeDistance
// acne may occur; the count is the measured failure (printed, not asserted: whether the error
// reaches its bound there depends on the device's rounding).
TEST_F(ShadowGrazing, NoAcneWhereTheReconstructionErrorIsBelowTheRaysRiseAtTMin) {
  const Acne a = measure(false);
  ASSERT_GT(a.nearPixels, 1000u);
  EXPECT_EQ(a.nearAcne, 0u);
}

// The remedy (t_min = "scaled"): t_min = max(0.001, 400u·d) rises t_min·N·L >= 4u·d above the
// plane wherever N·L >= 0.01, so no pixel with N·L >= 0.01 may be dark, at any distance. The
// plane reaches ~100 m, well past safeDistance, so the far pixels are there to be tested.
TEST_F(ShadowGrazing, ScaledTMinHasNoAcneAtAnyDistanceDownToNDotLOfOnePercent) {
  const Acne a = measure(true);
  ASSERT_GT(a.farPixels, 1000u);
  ASSERT_GT(a.steepPixels, 1000u);
  EXPECT_EQ(a.steepAcne, 0u);
  EXPECT_EQ(a.nearAcne, 0u);
}

// Far away and seen head-on ("grazing-far", 500 m), the reconstruction errs along the plane's
// normal by up to 4u·500 m = 1.2e-4 m, twelve times the constant t_min's rise of 1e-5 m at N·L =
// 0.01: the thesis's t_min gives acne there, and the count is the measured failure. The scene must
// show it (else the remedy below would be tested on nothing; lavapipe: see the printed line). The
// scaled t_min (0.012 m at 500 m, rising 1.2e-4 m at N·L = 0.01) must leave no dark pixel where
// N·L >= 0.01.
TEST_F(ShadowGrazing, FarAwayConstantTMinHasAcneAndScaledTMinHasNone) {
  const glm::dvec3 normal = grazingFarNormal();
  const Acne constant = measure(false, "grazing-far", normal);
  const Acne scaled = measure(true, "grazing-far", normal);
  ASSERT_GT(scaled.steepPixels, 10000u);
  EXPECT_GT(constant.steepAcne, 0u) << "the scene no longer exercises the constant t_min's failure";
  EXPECT_EQ(scaled.steepAcne, 0u);
}

}  // namespace
}  // namespace hb
