// Hard case: a light at grazing incidence (N·L = 0.01) on a large plane. A shadow ray leaves the
// reconstructed point at a slope of 0.01, so after t_min = 0.001 it has risen 1e-5 m; a point that
// depth reconstruction placed more than that below the plane hits the plane itself ("shadow acne").
// The reconstruction error grows with distance (about |P − eye|·4u, u = 2^-24: 1e-5 m at ~40 m),
// so the thesis's constant t_min must fail somewhere far away. This test measures where, and
// asserts that near the camera, where the error bound stays below the ray's rise, there is none.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "gpu_fixture.h"
#include "hard_cases.h"
#include "renderer.h"
#include "shared/gpu_types.h"

namespace hb {
namespace {

class ShadowGrazing : public testing::GpuTest {};

TEST_F(ShadowGrazing, NoAcneWhereTheReconstructionErrorIsBelowTheRaysRiseAtTMin) {
  Scene scene = makeBuiltinScene("grazing");
  RenderSettings s;
  s.width = 320;
  s.height = 180;
  s.tileSize = 16;
  s.normals = gpu::kNormalsOff;  // every pixel traces its ray: acne is the only way to be dark
  Renderer renderer(*ctx, scene, s);
  renderer.renderFrame(true);
  const ShadowReadback sh = renderer.readShadows();
  const std::vector<float> depth = renderer.readDepth();
  const glm::vec3 eye = glm::vec3(glm::inverse(scene.cameras[0].view)[3]);
  // Rise of the ray at t_min: 0.001 * 0.01 = 1e-5 m. Reconstruction error bound: 4u per unit of
  // distance to the eye (Alg. 4.1, tested in shadows_gpu_test) => safe while 4u·d < 1e-5, i.e.
  // d < 1e-5 / (4 * 2^-24) ≈ 42 m.
  const double safeDistance = 1e-5 / (4.0 * std::ldexp(1.0, -24));
  uint64_t nearPixels = 0, nearAcne = 0, farPixels = 0, farAcne = 0;
  for (size_t i = 0; i < depth.size(); ++i) {
    if (!(depth[i] > 0.0f)) continue;
    const uint32_t traced = (sh.accounting[i] >> gpu::kAccountTracedShift) & gpu::kAccountMask;
    if (traced == 0) continue;  // the light is not in this pixel's tile list (out of range)
    const glm::vec3 p(sh.positions[i * 4], sh.positions[i * 4 + 1], sh.positions[i * 4 + 2]);
    const double d = glm::length(p - eye);
    const bool dark = (sh.visibility[i] & 1u) == 0;
    (d < safeDistance ? nearPixels : farPixels)++;
    (d < safeDistance ? nearAcne : farAcne) += dark;
  }
  std::printf("grazing N.L=0.01: %llu/%llu acne pixels within %.0f m of the eye, %llu/%llu beyond\n",
              (unsigned long long)nearAcne, (unsigned long long)nearPixels, safeDistance,
              (unsigned long long)farAcne, (unsigned long long)farPixels);
  ASSERT_GT(nearPixels, 1000u);
  EXPECT_EQ(nearAcne, 0u);
}

}  // namespace
}  // namespace hb
