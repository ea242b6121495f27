#include "reference/flip.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "base/errors.h"

namespace hb {
namespace {

ImageRGBA8 uniformImage(uint32_t w, uint32_t h, uint8_t r, uint8_t g, uint8_t b) {
  ImageRGBA8 img{w, h, {}};
  for (size_t i = 0; i < size_t(w) * h; ++i) img.px.insert(img.px.end(), {r, g, b, 255});
  return img;
}

ImageRGBA8 noiseImage(uint32_t w, uint32_t h, uint32_t seed) {
  std::mt19937 rng(seed);
  ImageRGBA8 img{w, h, {}};
  for (size_t i = 0; i < size_t(w) * h; ++i)
    img.px.insert(img.px.end(), {uint8_t(rng()), uint8_t(rng()), uint8_t(rng()), 255});
  return img;
}

TEST(Flip, DefaultViewingSetupIsAbout67PixelsPerDegree) {
  // 0.7 m * (3840 px / 0.7 m) * pi/180 = 3840 * pi / 180 = 67.02064...
  EXPECT_NEAR(kDefaultPpd, 3840.0 * 3.14159265358979 / 180.0, 1e-9);
  EXPECT_NEAR(kDefaultPpd, 67.0206, 1e-4);
}

TEST(Flip, IdenticalImagesGiveExactlyZeroEverywhere) {
  // Both images take the same arithmetic path, so every intermediate is bit-identical: HyAB is
  // exactly 0, the feature difference exactly 0, and 0^(1-0) = 0.
  const ImageRGBA8 img = noiseImage(37, 23, 7);
  const FlipResult r = ldrFlip(img, img);
  ASSERT_EQ(r.errorMap.px.size(), size_t(37) * 23);
  EXPECT_EQ(r.errorMap.channels, 1u);
  for (float e : r.errorMap.px) ASSERT_EQ(e, 0.0f);
  EXPECT_EQ(r.mean, 0.0);
  EXPECT_EQ(r.max, 0.0);
}

TEST(Flip, AOnePixelChangeStaysWithinTheFilterSupport) {
  // Both filters have finite support of radius R = flipSupportRadius(ppd) (Chebyshev distance,
  // separable square kernels), so pixels farther than R from the change see bit-identical inputs
  // and must have exactly zero error; the changed pixel itself must have a clearly visible error.
  for (double ppd : {20.0, kDefaultPpd}) {
    const uint32_t size = 48, cx = 20, cy = 27;
    const ImageRGBA8 ref = uniformImage(size, size, 90, 110, 130);
    ImageRGBA8 test = ref;
    test.px[4 * (size_t(cy) * size + cx) + 0] = 255;
    const FlipResult r = ldrFlip(ref, test, ppd);
    const int radius = flipSupportRadius(ppd);
    size_t argmax = 0;
    for (uint32_t y = 0; y < size; ++y)
      for (uint32_t x = 0; x < size; ++x) {
        const size_t i = size_t(y) * size + x;
        if (r.errorMap.px[i] > r.errorMap.px[argmax]) argmax = i;
        if (std::max(std::abs(int(x) - int(cx)), std::abs(int(y) - int(cy))) > radius) {
          ASSERT_EQ(r.errorMap.px[i], 0.0f) << "ppd " << ppd << " at " << x << "," << y;
        }
      }
    EXPECT_GT(r.errorMap.px[size_t(cy) * size + cx], 0.1f) << ppd;
    const int ax = int(argmax % size), ay = int(argmax / size);
    EXPECT_LE(std::max(std::abs(ax - int(cx)), std::abs(ay - int(cy))), radius) << ppd;
  }
}

TEST(Flip, ErrorGrowsMonotonicallyWithAUniformColourShift) {
  // For uniform images the feature responses are equal (both ~0), so the error is the colour
  // term alone: a monotone compression of HyAB^qc, and HyAB grows with the size of a shift
  // along a fixed direction (lightness for grey, lightness+chroma for red).
  for (int channelMask : {7, 1}) {
    double previous = 0;
    for (int shift : {1, 3, 8, 20, 50, 100, 155}) {
      const ImageRGBA8 ref = uniformImage(24, 24, 100, 100, 100);
      const auto shifted = [&](int bit) { return uint8_t(channelMask & bit ? 100 + shift : 100); };
      const ImageRGBA8 test = uniformImage(24, 24, shifted(1), shifted(2), shifted(4));
      const FlipResult r = ldrFlip(ref, test);
      EXPECT_GT(r.mean, previous) << "mask " << channelMask << " shift " << shift;
      previous = r.mean;
    }
  }
}

TEST(Flip, ErrorsLieInTheUnitIntervalAndStatisticsAreOrdered) {
  for (uint32_t seed : {1u, 2u, 3u}) {
    const FlipResult r = ldrFlip(noiseImage(40, 30, seed), noiseImage(40, 30, seed + 100));
    for (float e : r.errorMap.px) {
      ASSERT_TRUE(std::isfinite(e));
      ASSERT_GE(e, 0.0f);
      ASSERT_LE(e, 1.0f);
    }
    EXPECT_LE(r.p50, r.p95);
    EXPECT_LE(r.p95, r.max);
    EXPECT_LE(r.mean, r.max);
    EXPECT_GT(r.mean, 0.0);
  }
}

TEST(Flip, IsSymmetricInItsTwoImages) {
  // HyAB and the absolute feature difference are symmetric, so swapping is bit-exact.
  const ImageRGBA8 a = noiseImage(20, 16, 11), b = noiseImage(20, 16, 12);
  EXPECT_EQ(ldrFlip(a, b).errorMap.px, ldrFlip(b, a).errorMap.px);
}

TEST(Flip, BlackAgainstWhiteIsCloseToOne) {
  // Uniform black vs white: features cancel (Ef = 0), so E = Ec. White is L = 100, a = b = 0;
  // black is L = 0: HyAB = 100. cmax from the published CIELAB (D65) of sRGB green
  // (87.7347, -86.1827, 83.1793) and blue (32.3026, 79.1967, -107.8637), Hunt-adjusted
  // (a, b scaled by L/100). Error budget: the 4-decimal Lab values move HyAB(green, blue) by
  // < 5e-4, i.e. cmax by < 1e-6 relative; float storage of L, a, b moves HyAB(black, white) by
  // < 1e-4; Ec's slope is 0.05/(0.6 cmax) * 0.7 HyAB^-0.3 < 4e-4 per unit HyAB. Both effects
  // stay below 1e-6, so 1e-5 is a safe bound.
  const double gl = 87.7347, ga = -86.1827 * 0.877347, gb = 83.1793 * 0.877347;
  const double bl = 32.3026, ba = 79.1967 * 0.323026, bb = -107.8637 * 0.323026;
  const double cmax = std::pow(std::abs(gl - bl) + std::hypot(ga - ba, gb - bb), 0.7);
  const double d = std::pow(100.0, 0.7);
  ASSERT_GT(d, 0.4 * cmax);  // in the compressed upper branch
  const double expected = 0.95 + (d - 0.4 * cmax) / (0.6 * cmax) * 0.05;

  const FlipResult r = ldrFlip(uniformImage(16, 16, 0, 0, 0), uniformImage(16, 16, 255, 255, 255));
  for (float e : r.errorMap.px) ASSERT_NEAR(e, expected, 1e-5);
  EXPECT_GT(r.mean, 0.95);
}

TEST(Flip, ImagesOfDifferentSizesAreAnInputError) {
  EXPECT_THROW(ldrFlip(uniformImage(4, 4, 0, 0, 0), uniformImage(4, 5, 0, 0, 0)), InputError);
}

}  // namespace
}  // namespace hb
