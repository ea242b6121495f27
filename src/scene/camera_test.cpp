#include "scene/camera.h"
#include "scene/scene.h"

#include <cmath>

#include <gtest/gtest.h>

namespace hb {
namespace {

// Eq. 2.1's structure: A on [0][0], B = -1/tan on [1][1] (Vulkan y down), C and D in the third
// row, -1 in the fourth row's z column, zeros elsewhere.
TEST(Projection, HasTheStructureOfThesisEquation21) {
  const double aspect = 16.0 / 9.0, fov = 1.0471975511965976, zn = 0.1, zf = 100.0;
  glm::dmat4 p = reverseZProjectionD(aspect, fov, zn, zf);
  const double t = std::tan(fov / 2);
  EXPECT_DOUBLE_EQ(p[0][0], 1.0 / (aspect * t));
  EXPECT_DOUBLE_EQ(p[1][1], -1.0 / t);
  EXPECT_DOUBLE_EQ(p[2][2], zn / (zf - zn));
  EXPECT_DOUBLE_EQ(p[3][2], zf * zn / (zf - zn));
  EXPECT_DOUBLE_EQ(p[2][3], -1.0);
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) {
      bool structural =
          (c == 0 && r == 0) || (c == 1 && r == 1) || (c == 2 && r == 2) || (c == 3 && r == 2) || (c == 2 && r == 3);
      if (!structural) {
        EXPECT_EQ(p[c][r], 0.0) << c << "," << r;
      }
    }
}

double ndcDepth(const glm::dmat4& p, double zView) {
  glm::dvec4 clip = p * glm::dvec4(0, 0, zView, 1);
  return clip.z / clip.w;
}

TEST(Projection, ReverseZMapsNearToOneAndFarToZero) {
  glm::dmat4 p = reverseZProjectionD(1.0, 1.0, 0.1, 1000.0);
  EXPECT_NEAR(ndcDepth(p, -0.1), 1.0, 1e-15);
  EXPECT_NEAR(ndcDepth(p, -1000.0), 0.0, 1e-15);
  // Monotone: farther is smaller (so the depth test is GREATER_OR_EQUAL and the clear value 0).
  EXPECT_GT(ndcDepth(p, -1.0), ndcDepth(p, -2.0));
}

TEST(Projection, PrintedEquation21IsNotReverseZErratum) {
  // The matrix exactly as printed (C = -zf/(zn-zf), D = -zf*zn/(zn-zf)) maps near to 0 and far
  // to -1: this is why camera.h implements the reverse-Z matrix the text describes instead.
  const double zn = 0.1, zf = 1000.0;
  glm::dmat4 printed = reverseZProjectionD(1.0, 1.0, zn, zf);
  printed[2][2] = -zf / (zn - zf);
  printed[3][2] = -zf * zn / (zn - zf);
  EXPECT_NEAR(ndcDepth(printed, -zn), 0.0, 1e-12);
  EXPECT_NEAR(ndcDepth(printed, -zf), -1.0, 1e-12);
}

// The inverse of eq. 4.3: view z = -D / (depth + C) recovers the view depth.
TEST(Projection, Equation43InvertsTheDepthMapping) {
  glm::dmat4 p = reverseZProjectionD(1.5, 0.9, 0.05, 500.0);
  for (double z : {-0.05, -0.3, -7.0, -123.0, -500.0}) {
    double d = ndcDepth(p, z);
    double back = -p[3][2] / (d + p[2][2]);
    EXPECT_NEAR(back, z, 1e-12 * std::abs(z));
  }
}

// The orthographic matrix: near to 1, far to 0, affine in view depth between (so t = (D - depth)/C
// recovers it), and the view's extent xmag x ymag to NDC ±1 with y down.
TEST(Projection, OrthographicIsReverseZAndAffineInViewDepth) {
  const double xmag = 3.5, ymag = 2.0, zn = 0.05, zf = 500.0;
  const glm::dmat4 p = reverseZOrthographicD(xmag, ymag, zn, zf);
  EXPECT_NEAR(ndcDepth(p, -zn), 1.0, 1e-15);
  EXPECT_NEAR(ndcDepth(p, -zf), 0.0, 1e-15);
  for (double z : {-0.05, -0.3, -7.0, -123.0, -500.0}) {
    const double d = ndcDepth(p, z);
    EXPECT_NEAR((p[3][2] - d) / p[2][2], -z, 1e-12 * std::abs(z));
  }
  const glm::dvec4 corner = p * glm::dvec4(xmag, ymag, -10.0, 1.0);
  EXPECT_DOUBLE_EQ(corner.w, 1.0);
  EXPECT_DOUBLE_EQ(corner.x, 1.0);
  EXPECT_DOUBLE_EQ(corner.y, -1.0);  // up in view space is up on screen: NDC y = -1 (Vulkan)
}

TEST(Projection, LightRangeFromEquation41) {
  // I / D^2 = 0.02  <=>  D = 50 sqrt(0.02 I)
  for (double intensity : {0.5, 1.0, 10.0, 250.0}) {
    double d = rangeFromIntensity(intensity);
    EXPECT_NEAR(intensity / (d * d), 0.02, 1e-15);
  }
  EXPECT_DOUBLE_EQ(rangeFromIntensity(50.0), 50.0);  // 50 * sqrt(1) = 50
}

}  // namespace
}  // namespace hb
