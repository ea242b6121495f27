// effects.indirect.later_bounce_stride on the real device (shaders/indirect/photon_splat_gather.glsl.inc
// lateAt, effects/indirect/indirect_pass.cpp recordComputeSplat): bounces 2..K splatted at one
// receiver pixel in f x f, then interpolated on each pixel's own surface. At the receivers the frame
// is the exact splat's sum, to float rounding of a different association; elsewhere each pixel's
// later light is 0 or lies between its neighbouring receivers'; the first bounce is untouched; the
// frame is deterministic. Bad strides: indirect_bounces_gpu_test.cpp's settings test.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "effects/indirect/indirect_effect.h"
#include "effects/indirect/indirect_part.h"
#include "frame/renderer.h"
#include "gpu_fixture.h"
#include "indirect_test_scenes.h"

namespace hb {
namespace {

using namespace indirect_testing;  // indirect_test_scenes.h

constexpr double kU = 0x1p-24;  // float's unit roundoff
constexpr uint32_t kStrideW = 128, kStrideH = 80;

struct StrideFrame {
  std::vector<float> e;
  std::vector<gpu::Photon> photons;
};

class IndirectLaterStrideGpuTest : public testing::GpuTest {
 protected:
  StrideFrame render(const Scene& scene, uint32_t bounces, uint32_t stride, bool twice = false);
};

StrideFrame IndirectLaterStrideGpuTest::render(const Scene& scene, uint32_t bounces, uint32_t stride, bool twice) {
  Renderer r(*ctx, scene,
             indirectSettings(kStrideW, kStrideH,
                              {{"method", "raytraced"},
                               {"directions", 32},
                               {"photons", 4},
                               {"bounces", bounces},
                               {"bounce_directions", 4},
                               {"splat_bin", 64},
                               {"later_bounce_stride", stride}}));
  r.renderFrame(true);
  StrideFrame f{indirectPassOf(r)->readIrradiance(), indirectPassOf(r)->readPhotons()};
  if (twice) {
    r.renderFrame(true);
    EXPECT_EQ(indirectPassOf(r)->readIrradiance(), f.e) << "a second frame at stride " << stride << " differs";
  }
  return f;
}

// The block box (walls, a floating block: edges, corners and depth steps), K = 2.
//  - The photons do not depend on the stride: the same slots bit for bit.
//  - K = 1 at a stride is K = 1 exactly (the stride touches only bounces 2..K).
//  - At a receiver (pixel i·f + f/2), the stride's frame is fl(S1 + L): S1 the first bounce's terms
//    summed in slot order (the K = 1 frame's value there, bit for bit), L the later bounces' terms
//    summed in slot order from 0. The exact splat sums the same n terms in one run. Each float
//    sum of n non-negative terms is within γ_n = nu/(1 − nu) of their real sum T (Higham, recursive
//    summation), so |E_f − E_1| <= 2γ_n·T <= 2γ_n/(1 − γ_n)·E_exact, with n at most the stored
//    photons of the frame. A receiver taken one pixel off, or its coverage tested elsewhere, moves
//    the value by the kernel's slope times a pixel, far beyond that.
//  - Elsewhere the later light Δ = E_f − E_1 (its add rounded: ±u·E_f) is 0 (no receiver on the
//    pixel's surface within 4x4) or a convex combination of the 4x4 receivers' L: within
//    [min L, max L] of that window, each L itself known to ±u·E_f(r).
TEST_F(IndirectLaterStrideGpuTest, AtTheReceiversTheFrameIsTheExactSplatAndBetweenThemAnInterpolation) {
  const Scene scene = diffuseBox("block-box", true);
  const StrideFrame one = render(scene, 1, 1), oneAt4 = render(scene, 1, 4);
  EXPECT_EQ(one.e, oneAt4.e) << "K = 1 changed by the stride";
  const StrideFrame exact = render(scene, 2, 1);
  uint64_t stored = 0;
  for (const gpu::Photon& p : exact.photons) stored += statusOf(p) == gpu::kPhotonStored;
  const double gamma = double(stored) * kU / (1.0 - double(stored) * kU);
  const double bound = 2.0 * gamma / (1.0 - gamma);
  ASSERT_GT(stored, 1000u);
  for (uint32_t f : {2u, 4u}) {
    SCOPED_TRACE("stride " + std::to_string(f));
    const StrideFrame strided = render(scene, 2, f, true);
    ASSERT_EQ(strided.photons.size(), exact.photons.size());
    ASSERT_EQ(std::memcmp(strided.photons.data(), exact.photons.data(), exact.photons.size() * sizeof(gpu::Photon)), 0)
        << "the photons differ";
    const uint32_t cw = (kStrideW + f - 1) / f, ch = (kStrideH + f - 1) / f;
    auto at = [](const std::vector<float>& e, uint32_t x, uint32_t y, int c) {
      return double(e[(y * kStrideW + x) * 4 + c]);
    };
    // The receivers: the exact splat's sum there.
    size_t receivers = 0, lateLit = 0, beyond = 0;
    double worst = 0;
    std::vector<double> late(size_t(cw) * ch * 3, 0.0), lateSlack(late.size(), 0.0);
    for (uint32_t j = 0; j < ch; ++j)
      for (uint32_t i = 0; i < cw; ++i) {
        const uint32_t x = std::min(i * f + f / 2, kStrideW - 1), y = std::min(j * f + f / 2, kStrideH - 1);
        ++receivers;
        for (int c = 0; c < 3; ++c) {
          const double got = at(strided.e, x, y, c), want = at(exact.e, x, y, c);
          const double diff = std::abs(got - want);
          beyond += diff > bound * want;
          if (want > 0) worst = std::max(worst, diff / want);
          late[(size_t(j) * cw + i) * 3 + c] = got - at(one.e, x, y, c);
          lateSlack[(size_t(j) * cw + i) * 3 + c] = kU * got;
          lateLit += c == 0 && got > at(one.e, x, y, c);
        }
      }
    // Between the receivers: 0 or within the 4x4 window's range.
    size_t outside = 0, dark = 0, lit = 0;
    for (uint32_t y = 0; y < kStrideH; ++y)
      for (uint32_t x = 0; x < kStrideW; ++x) {
        const int i0 = int(std::floor((double(x) - f / 2) / f)), j0 = int(std::floor((double(y) - f / 2) / f));
        for (int c = 0; c < 3; ++c) {
          const double d = at(strided.e, x, y, c) - at(one.e, x, y, c), slack = kU * at(strided.e, x, y, c);
          if (std::abs(d) <= slack) {
            dark += c == 0 && at(exact.e, x, y, c) > at(one.e, x, y, c);
            continue;
          }
          lit += c == 0;
          double lo = 1e300, hi = -1e300;
          for (int jj = j0 - 1; jj <= j0 + 2; ++jj)
            for (int ii = i0 - 1; ii <= i0 + 2; ++ii) {
              if (ii < 0 || jj < 0 || ii >= int(cw) || jj >= int(ch)) continue;
              const size_t k = (size_t(jj) * cw + ii) * 3 + c;
              lo = std::min(lo, late[k] - lateSlack[k]);
              hi = std::max(hi, late[k] + lateSlack[k]);
            }
          outside += d < lo - slack || d > hi + slack;
        }
      }
    std::printf(
        "block box %ux%u, K = 2, stride %u: %zu receivers (%zu with later light), %llu stored photons: largest "
        "relative difference from the exact splat %.3g (bound 2γ_n = %.3g), %zu values beyond; %zu pixels with "
        "later light, %zu outside their receivers' range, %zu left without (the exact splat lights them)\n",
        kStrideW, kStrideH, f, receivers, lateLit, (unsigned long long)stored, worst, bound, beyond, lit, outside,
        dark);
    EXPECT_EQ(beyond, 0u);
    EXPECT_GT(lateLit, receivers / 2);
    EXPECT_EQ(outside, 0u);
    EXPECT_GT(lit, size_t(kStrideW) * kStrideH / 2);
  }
}

}  // namespace
}  // namespace hb
