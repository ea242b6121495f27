#include "reference/reconstruct_ref.h"
#include "base/numbers.h"

#include <cmath>
#include <functional>
#include <optional>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "scene/camera.h"

namespace hb {
namespace {

constexpr double kUd = 0x1p-53;  // double unit roundoff

struct PlaneGeom {
  glm::dvec3 n;  // unit
  glm::dvec3 p0;
};

// An analytic view: camera, and per pixel the plane it sees (or none = sky).
struct View {
  uint32_t width, height;
  glm::dmat4 view, proj;
  ReconstructionCamera<double> cam;
  glm::dvec3 eye;

  View(uint32_t w, uint32_t h, glm::dvec3 eyePos, glm::dvec3 target) : width(w), height(h), eye(eyePos) {
    view = glm::lookAtRH(eyePos, target, glm::dvec3(0, 1, 0));
    proj = reverseZProjectionD(double(w) / h, 1.0471975512, 0.1, 100.0);
    cam = reconstructionCamera(view, proj, w, h);
  }
  // Ray parameter along the view-space direction (ndc.x/A, ndc.y/B, -1) of pixel (x, y): the hit
  // has view z = -t and reverse-Z depth D/t - C.
  std::optional<double> hitT(uint32_t x, uint32_t y, const PlaneGeom& pl) const {
    const double nx = ((x + 0.5) / width) * 2 - 1, ny = ((y + 0.5) / height) * 2 - 1;
    const glm::dvec3 dirView(nx / proj[0][0], ny / proj[1][1], -1.0);
    const glm::dvec3 dirWorld = glm::dmat3(cam.viewInv) * dirView;
    const double t = glm::dot(pl.n, pl.p0 - eye) / glm::dot(pl.n, dirWorld);
    if (!(t > 0.1 && t < 100.0)) return std::nullopt;
    return t;
  }
  glm::dvec3 pointAt(uint32_t x, uint32_t y, double t) const {
    const double nx = ((x + 0.5) / width) * 2 - 1, ny = ((y + 0.5) / height) * 2 - 1;
    return eye + glm::dmat3(cam.viewInv) * glm::dvec3(nx / proj[0][0], ny / proj[1][1], -1.0) * t;
  }
  // Depth image (float, as the GPU stores it) of the planes chosen per pixel.
  std::vector<float> depth(const std::function<const PlaneGeom*(uint32_t, uint32_t)>& planeAt) const {
    std::vector<float> d(size_t(width) * height, 0.0f);
    for (uint32_t y = 0; y < height; ++y)
      for (uint32_t x = 0; x < width; ++x)
        if (const PlaneGeom* pl = planeAt(x, y))
          if (auto t = hitT(x, y, *pl)) d[size_t(y) * width + x] = float(proj[3][2] / *t - proj[2][2]);
    return d;
  }
};

// Position error bound from the float depth alone: P_view = ray * D/(d + C), so |dP/dd| =
// |P_view|/(d + C) and |δd| <= u·d: |δP| <= |P - eye|·u·d/(d + C) <= |P - eye|·u.
double depthRoundingBound(const View& v, const glm::dvec3& p) { return glm::length(p - v.eye) * kU; }

TEST(Reconstruction, PositionsMatchTheAnalyticPlanePoints) {
  const View v(64, 48, {3, 4, 10}, {0, 0, 0});
  const PlaneGeom ground{{0, 1, 0}, {0, 0, 0}};
  const auto depth = v.depth([&](uint32_t, uint32_t) { return &ground; });
  // The plain variant's inverse(viewProj) adds about cond(viewProj)·8 ulps (inverse + product).
  const glm::dmat4 vp = v.proj * v.view;
  double cond = 0.0, n1 = 0.0, n2 = 0.0;
  for (int i = 0; i < 4; ++i) n1 += glm::dot(vp[i], vp[i]), n2 += glm::dot(v.cam.viewProjInv[i], v.cam.viewProjInv[i]);
  cond = std::sqrt(n1 * n2);
  int checked = 0;
  for (uint32_t y = 0; y < v.height; ++y)
    for (uint32_t x = 0; x < v.width; ++x) {
      const auto t = v.hitT(x, y, ground);
      if (!t) continue;
      const glm::dvec3 truth = v.pointAt(x, y, *t);
      const double d = depth[size_t(y) * v.width + x];
      // Double arithmetic of Alg. 4.1: ~12 roundings of magnitude |P_view| + |eye|.
      const double bound = depthRoundingBound(v, truth) + 16 * kUd * (glm::length(truth - v.eye) + glm::length(v.eye));
      EXPECT_LE(glm::length(worldFromDepth(v.cam, x, y, d) - truth), bound);
      const double plainBound = bound + 8 * cond * kUd * (glm::length(truth) + 1.0);
      EXPECT_LE(glm::length(worldFromDepthPlain(v.cam, x, y, d) - truth), plainBound);
      ++checked;
    }
  EXPECT_GT(checked, 1000);
}

// First-order angular error of n = a×b/|a×b| under errors δa, δb (each ≤ the sum of its two
// endpoints' position errors): |δn| ≤ (|δa|/|a| + |δb|/|b|) / sin(angle(a, b)).
double normalBound(const glm::dvec3& a, const glm::dvec3& b, double da, double db) {
  const double sinAB = glm::length(glm::cross(a, b)) / (glm::length(a) * glm::length(b));
  return (da / glm::length(a) + db / glm::length(b)) / sinAB;
}

double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

// For a plane, every derivative either method can pick joins two neighbouring samples on the
// plane; the bound takes the worst of the pixel's x and y neighbour pairs.
template <typename T>
void expectPlaneNormals(const View& v, const PlaneGeom& pl, NormalMethod method, double perPointExtra) {
  const auto depth = v.depth([&](uint32_t, uint32_t) { return &pl; });
  ReconstructionCamera<T> cam =
      reconstructionCamera(glm::mat<4, 4, T>(v.view), glm::mat<4, 4, T>(v.proj), v.width, v.height);
  int checked = 0;
  for (uint32_t y = 1; y + 1 < v.height; ++y)
    for (uint32_t x = 1; x + 1 < v.width; ++x) {
      const auto t0 = v.hitT(x, y, pl), tx0 = v.hitT(x - 1, y, pl), tx1 = v.hitT(x + 1, y, pl);
      const auto ty0 = v.hitT(x, y - 1, pl), ty1 = v.hitT(x, y + 1, pl);
      if (!t0 || !tx0 || !tx1 || !ty0 || !ty1) continue;
      const glm::dvec3 p = v.pointAt(x, y, *t0);
      const glm::dvec3 a = glm::length(v.pointAt(x - 1, y, *tx0) - p) < glm::length(v.pointAt(x + 1, y, *tx1) - p)
                               ? p - v.pointAt(x - 1, y, *tx0)
                               : v.pointAt(x + 1, y, *tx1) - p;
      const glm::dvec3 b = glm::length(v.pointAt(x, y - 1, *ty0) - p) < glm::length(v.pointAt(x, y + 1, *ty1) - p)
                               ? p - v.pointAt(x, y - 1, *ty0)
                               : v.pointAt(x, y + 1, *ty1) - p;
      // Position error per sample (about the same for neighbours): depth rounding + arithmetic.
      const double e =
          1.01 * (depthRoundingBound(v, p) + perPointExtra * (glm::length(p - v.eye) + glm::length(v.eye)));
      bool ok = false;
      const glm::dvec3 n = glm::dvec3(reconstructNormal(depth, cam, x, y, method, &ok));
      ASSERT_TRUE(ok);
      const glm::dvec3 truth = glm::dot(pl.n, v.eye - p) >= 0 ? pl.n : -pl.n;
      EXPECT_LE(angleBetween(n, truth), normalBound(a, b, 2 * e, 2 * e)) << x << "," << y;
      ++checked;
    }
  EXPECT_GT(checked, 500);
}

const PlaneGeom kGround{{0, 1, 0}, {0, 0, 0}};
const PlaneGeom kTilted{glm::normalize(glm::dvec3(1, 2, 3)), {0, 0, -2}};

TEST(Reconstruction, PlanesGiveExactNormalsInDouble) {
  const View v(64, 48, {3, 4, 10}, {0, 0, 0});
  for (auto m : {NormalMethod::Naive, NormalMethod::Improved}) {
    expectPlaneNormals<double>(v, kGround, m, 16 * kUd);
    expectPlaneNormals<double>(v, kTilted, m, 16 * kUd);
  }
}

// Float mirrors the GPU: Alg. 4.1 in float adds ≤ 6 roundings on |P_view| (ndc, /A, +C, /D, /w)
// and the 4-term product with viewInv γ4·(|P_view| + |eye|), and the difference one more: 12u.
TEST(Reconstruction, PlanesGiveExactNormalsInFloatWithinDerivedBound) {
  const View v(64, 48, {3, 4, 10}, {0, 0, 0});
  for (auto m : {NormalMethod::Naive, NormalMethod::Improved}) {
    expectPlaneNormals<float>(v, kGround, m, 12 * kU);
    expectPlaneNormals<float>(v, kTilted, m, 12 * kU);
  }
}

TEST(Reconstruction, DepthStepKeepsEachSidesPlaneNormalWithImproved) {
  const View v(64, 48, {0, 0, 10}, {0, 0, 0});
  // Left half sees a wall tilted about y at z≈0, right half the ground 3 units below.
  const PlaneGeom wall{glm::normalize(glm::dvec3(0.3, 0, 1)), {0, 0, 0}};
  const PlaneGeom floorPlane{{0, 1, 0}, {0, -3, 0}};
  const uint32_t step = 32;
  const auto depth = v.depth([&](uint32_t x, uint32_t) { return x < step ? &wall : &floorPlane; });
  int naiveWrong = 0, checked = 0;
  for (uint32_t y = 26; y < 46; ++y)  // rows where the floor is visible on the right
    for (uint32_t x = step - 2; x < step + 2; ++x) {
      const PlaneGeom& pl = x < step ? wall : floorPlane;
      if (!v.hitT(x, y, floorPlane) || !v.hitT(x, y, wall)) continue;
      bool ok = false;
      const glm::dvec3 n = reconstructNormal(depth, v.cam, x, y, NormalMethod::Improved, &ok);
      ASSERT_TRUE(ok);
      // Far from rounding: the sample error is ~1e-7 of the 1e-1 spacing; 1e-4 rad is 1000x that.
      EXPECT_LT(angleBetween(n, pl.n), 1e-4) << x << "," << y;
      const glm::dvec3 nn = reconstructNormal(depth, v.cam, x, y, NormalMethod::Naive, &ok);
      naiveWrong += angleBetween(nn, pl.n) > 1e-2;
      ++checked;
    }
  EXPECT_GT(checked, 40);
  EXPECT_GT(naiveWrong, 0);  // the naive method does cross the step (thesis Fig. 4.6 (1))
}

TEST(Reconstruction, SkyPixelsAreFlaggedAndNeverNaN) {
  const View v(33, 17, {0, 0, 10}, {0, 0, 0});  // odd width: the centre column has ndc.x = 0
  const PlaneGeom facing{{0, 0, 1}, {0, 0, 0}};
  const auto depth = v.depth([&](uint32_t x, uint32_t y) { return (x + y) % 7 == 3 || x == 20 ? nullptr : &facing; });
  for (auto m : {NormalMethod::Naive, NormalMethod::Improved}) {
    const auto img = reconstructImage(depth, v.cam, m);
    for (size_t i = 0; i < img.size(); ++i) {
      const auto& p = img[i];
      EXPECT_EQ(p.sky, depth[i] == 0.0f);
      EXPECT_TRUE(std::isfinite(p.position.x + p.position.y + p.position.z + p.normal.x + p.normal.y + p.normal.z));
      if (p.sky) {
        EXPECT_FALSE(p.hasNormal);
        EXPECT_EQ(p.normal, glm::dvec3(0.0));
      } else if (p.hasNormal) {
        EXPECT_NEAR(glm::length(p.normal), 1.0, 1e-15);
        EXPECT_LT(angleBetween(p.normal, facing.n), 1e-6);  // plane: as above, far from rounding
      }
    }
    // The centre column (x = 16) has a normal wherever it and a neighbour per axis are not sky.
    auto geo = [&](int64_t x, int64_t y) {
      return x >= 0 && y >= 0 && x < int64_t(v.width) && y < int64_t(v.height) &&
             depth[size_t(y) * v.width + size_t(x)] > 0.0f;
    };
    int centre = 0;
    for (int64_t y = 0; y < int64_t(v.height); ++y) {
      if (!geo(16, y) || !(geo(15, y) || geo(17, y)) || !(geo(16, y - 1) || geo(16, y + 1))) continue;
      EXPECT_TRUE(img[size_t(y) * v.width + 16].hasNormal) << y;
      ++centre;
    }
    EXPECT_GT(centre, 5);
  }
  // A one-pixel-wide image has no x neighbour: no normal, no NaN.
  const View thin(1, 8, {0, 0, 10}, {0, 0, 0});
  const auto d1 = thin.depth([&](uint32_t, uint32_t) { return &facing; });
  bool ok = true;
  const glm::dvec3 n = reconstructNormal(d1, thin.cam, 0, 3, NormalMethod::Improved, &ok);
  EXPECT_FALSE(ok);
  EXPECT_EQ(n, glm::dvec3(0.0));
}

TEST(Reconstruction, BordersUseTheSamplesThatExist) {
  const View v(16, 12, {3, 4, 10}, {0, 0, 0});
  const auto depth = v.depth([&](uint32_t, uint32_t) { return &kTilted; });
  for (auto m : {NormalMethod::Naive, NormalMethod::Improved})
    for (uint32_t y : {0u, 11u})
      for (uint32_t x : {0u, 1u, 14u, 15u}) {
        if (depth[size_t(y) * v.width + x] == 0.0f) continue;
        bool ok = false;
        const glm::dvec3 n = reconstructNormal(depth, v.cam, x, y, m, &ok);
        ASSERT_TRUE(ok);
        EXPECT_LT(angleBetween(n, kTilted.n), 1e-5);  // a plane; rounding ~1e-7 relative
      }
}

}  // namespace
}  // namespace hb
