// Thesis 4.3.2 / Algorithm 4.1 line 2: ndc = fma((p + 0.5) / w, 2, -1), Herbie's rewrite of
// ((p + 0.5) * (1 / w)) * 2 - 1, checked in float against exact arithmetic for every pixel centre
// of widths up to 8192.
#include <cmath>
#include <cstdint>

#include <gtest/gtest.h>

namespace hb {
namespace {

// Error bound of the fma form (u = 2^-24, t = (p + 0.5)/w in (0, 1)):
//   q = fl(t) = t(1 + d1)            p + 0.5 is exact in float for p < 2^23, the divide rounds once
//   r = fl(2q - 1) = (2q - 1)(1 + d2)  the fma rounds once
//   |r - (2t - 1)| <= 2t|d1| + |2t - 1 + 2t d1||d2| <= 2u + u + 2u^2 < 3.0001 u.
// The exact value (2p + 1 - w) / w is computed in double: its own error (2^-53 relative) is
// negligible against u.
TEST(NdcFromPixel, Algorithm41FmaFormIsWithinThreeUlpsOfExactForWidthsUpTo8192) {
  const double u = std::ldexp(1.0, -24);
  double worstFma = 0.0, worstNaive = 0.0;
  for (uint32_t w = 1; w <= 8192; w = w < 64 ? w + 1 : w * 2 - 1) {
    for (uint32_t p = 0; p < w; ++p) {
      const double exact = (2.0 * p + 1.0 - w) / w;
      const float fmaForm = std::fma((float(p) + 0.5f) / float(w), 2.0f, -1.0f);
      const float naive = ((float(p) + 0.5f) * (1.0f / float(w))) * 2.0f - 1.0f;
      worstFma = std::max(worstFma, std::abs(double(fmaForm) - exact));
      worstNaive = std::max(worstNaive, std::abs(double(naive) - exact));
      ASSERT_LE(std::abs(double(fmaForm) - exact), 3.0001 * u) << "w=" << w << " p=" << p;
    }
  }
  // The naive form rounds three more times (1/w, the product, the subtraction): it is never
  // better than the fma form's bound by construction, and here it is measurably worse.
  EXPECT_GE(worstNaive, worstFma);
  std::printf("worst |error| in units of 2^-24: fma form %.3f, naive form %.3f\n", worstFma / u, worstNaive / u);
}

// The centre column of an odd width maps to exactly 0 (no NaN, no sign flip), the thesis's
// "centre column of odd widths" case.
TEST(NdcFromPixel, CentreColumnOfOddWidthsIsExactlyZero) {
  for (uint32_t w = 1; w <= 8191; w += 2) {
    const uint32_t p = w / 2;
    const float ndc = std::fma((float(p) + 0.5f) / float(w), 2.0f, -1.0f);
    ASSERT_EQ(ndc, 0.0f) << "w=" << w;
  }
}

}  // namespace
}  // namespace hb
