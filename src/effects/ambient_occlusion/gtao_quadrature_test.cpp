// GTAO's slice integral (shaders/ambient_occlusion/ao_common.glsl.inc gtao) in double, under open
// sky: the closed form integrates to exactly 1 over the slices about the view vector; N evenly
// rotated slices leave a quadrature error, whose bound at N = 64 is the open-sky tolerance of
// tests/ao_gpu_test.cpp (kGtaoQuadrature64); and XeGTAO's slices, rotated on screen, are biased away
// from the image's centre (why the shader rotates them about the view vector).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>
#include <glm/glm.hpp>

namespace hb {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The unoccluded slice through V with + side T (orthogonal to V) for normal n: the shader's
// npLength · (arc(n + π/2) + arc(n − π/2)), both horizons at the tangent.
double unoccludedSlice(glm::dvec3 n, glm::dvec3 V, glm::dvec3 T) {
  const glm::dvec3 axis = glm::cross(T, V);
  const glm::dvec3 np = n - axis * glm::dot(n, axis);
  const double length = glm::length(np);
  if (!(length > 1e-9)) return 0.0;
  const double cosN = std::clamp(glm::dot(np, V) / length, -1.0, 1.0);
  const double angle = (glm::dot(np, T) >= 0.0 ? 1.0 : -1.0) * std::acos(cosN);
  auto arc = [&](double h) { return 0.25 * (cosN + 2.0 * h * std::sin(angle) - std::cos(2.0 * h - angle)); };
  return length * (arc(angle + kPi / 2) + arc(angle - kPi / 2));
}

// The mean over `slices` slices about V at rotation `rotation` (in slices), as the shader takes them.
double aboutV(glm::dvec3 n, glm::dvec3 V, int slices, double rotation) {
  const glm::dvec3 b1 = glm::normalize(glm::cross(V, std::abs(V.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0)));
  const glm::dvec3 b2 = glm::cross(V, b1);
  double sum = 0;
  for (int k = 0; k < slices; ++k) {
    const double phi = kPi * (k + rotation) / slices;
    sum += unoccludedSlice(n, V, std::cos(phi) * b1 + std::sin(phi) * b2);
  }
  return sum / slices;
}

// XeGTAO's slices: screen directions (cos φ, −sin φ) made orthogonal to V.
double onScreen(glm::dvec3 n, glm::dvec3 V, int slices) {
  double sum = 0;
  for (int k = 0; k < slices; ++k) {
    const double phi = kPi * (k + 0.5) / slices;
    const glm::dvec3 d(std::cos(phi), -std::sin(phi), 0.0);
    sum += unoccludedSlice(n, V, glm::normalize(d - glm::dot(d, V) * V));
  }
  return sum / slices;
}

glm::dvec3 tilted(glm::dvec3 V, double tilt, double azimuth) {
  const glm::dvec3 b1 = glm::normalize(glm::cross(V, glm::dvec3(0, 1, 0))), b2 = glm::cross(V, b1);
  return std::cos(tilt) * V + std::sin(tilt) * (std::cos(azimuth) * b1 + std::sin(azimuth) * b2);
}

TEST(GtaoQuadrature, TheUnoccludedSliceIntegratesToOneAboutTheViewVector) {
  const glm::dvec3 V = glm::normalize(glm::dvec3(0.4, 0.3, 1.0));
  for (double tilt : {0.0, 0.4, 1.2, 1.5}) EXPECT_NEAR(aboutV(tilted(V, tilt, 0.7), V, 20000, 0.5), 1.0, 1e-9) << tilt;
}

// The bound the GPU test's tolerance takes: normals up to 89.5 degrees from V (0.5-degree steps,
// every 15 degrees of azimuth), V up to 60 degrees off the view axis, three rotations.
TEST(GtaoQuadrature, SixtyFourSlicesAreWithinTheGpuTestsBoundOfOne) {
  double worst = 0;
  for (double viewTilt : {0.0, 20.0, 40.0, 60.0}) {
    const double a = viewTilt * kPi / 180;
    const glm::dvec3 V(std::sin(a), 0.0, std::cos(a));
    for (int t = 0; t < 180; ++t)
      for (int az = 0; az < 360; az += 15)
        for (double rotation : {0.0, 0.37, 0.81}) {
          const glm::dvec3 n = tilted(V, t * 0.5 * kPi / 180, az * kPi / 180);
          worst = std::max(worst, std::abs(aboutV(n, V, 64, rotation) - 1.0));
        }
  }
  std::printf("GTAO under open sky, 64 slices about V: largest |mean - 1| = %.3g\n", worst);
  EXPECT_LE(worst, 1.0e-4);  // tests/ao_gpu_test.cpp kGtaoQuadrature64
}

// XeGTAO's screen-rotated slices bunch about V away from the image's centre: with V 26.6 degrees off
// the axis they give too much light under open sky, far beyond the quadrature error above.
TEST(GtaoQuadrature, SlicesRotatedOnScreenAreBiasedOffAxis) {
  const glm::dvec3 V = glm::normalize(glm::dvec3(0.4, 0.3, 1.0)), n = glm::normalize(glm::dvec3(0.1, 1.0, 0.2));
  const double screen = onScreen(n, V, 4000), about = aboutV(n, V, 4000, 0.5);
  std::printf("GTAO under open sky, V 26.6 degrees off axis: slices on screen %.5f, about V %.5f\n", screen, about);
  EXPECT_NEAR(about, 1.0, 1e-9);
  EXPECT_GT(screen - 1.0, 0.005);
}

}  // namespace
}  // namespace hb
