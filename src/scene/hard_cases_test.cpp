#include "scene/hard_cases.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "base/errors.h"

namespace hb {
namespace {

// Twice the area of triangle i of primitive p (object space; every instance here is the identity).
double twiceArea(const Scene& s, const Primitive& p, uint32_t i) {
  const Vertex* v = &s.vertices[p.vertexOffset];
  const uint32_t* idx = &s.indices[p.firstIndex + i];
  const glm::dvec3 a(v[idx[0]].position), b(v[idx[1]].position), c(v[idx[2]].position);
  return glm::length(glm::cross(b - a, c - a));
}

uint64_t degenerateCount(const Scene& s) {
  uint64_t n = 0;
  for (const Mesh& m : s.meshes)
    for (const Primitive& p : m.primitives)
      for (uint32_t i = 0; i < p.indexCount; i += 3) n += twiceArea(s, p, i) == 0.0;
  return n;
}

TEST(HardCases, EveryBuiltinSceneBuildsFiniteWithALightAndACamera) {
  for (const std::string& name : builtinSceneNames()) {
    SCOPED_TRACE(name);
    const Scene s = makeBuiltinScene(name);
    EXPECT_EQ(s.name, name);
    EXPECT_GE(s.lights.size(), 1u);
    ASSERT_GE(s.cameras.size(), 1u);
    EXPECT_GT(s.triangleCount(), 0u);
    for (const Vertex& v : s.vertices) {
      ASSERT_TRUE(std::isfinite(v.position.x) && std::isfinite(v.position.y) && std::isfinite(v.position.z));
      ASSERT_TRUE(std::isfinite(v.normal.x) && std::isfinite(v.normal.y) && std::isfinite(v.normal.z));
    }
    for (const Light& l : s.lights) EXPECT_TRUE(std::isfinite(l.range) && l.range > 0.0f) << l.name;
    for (const Mesh& m : s.meshes)
      for (const Primitive& p : m.primitives) {
        ASSERT_LT(p.material, s.materials.size());
        ASSERT_LE(size_t(p.firstIndex) + p.indexCount, s.indices.size());
        for (uint32_t i = 0; i < p.indexCount; ++i) ASSERT_LT(s.indices[p.firstIndex + i], p.vertexCount);
      }
    const Camera& c = s.cameras[0];
    EXPECT_GT(c.znear, 0.0f);
    EXPECT_GT(c.zfar, c.znear);
  }
}

TEST(HardCases, OnlyTheDegenerateSceneHasDegenerateTriangles) {
  for (const std::string& name : builtinSceneNames()) {
    if (name == "atrium") continue;  // atrium_test covers it more strictly
    SCOPED_TRACE(name);
    const Scene s = makeBuiltinScene(name);
    EXPECT_EQ(degenerateCount(s), name == "degenerate" ? kDegenerateCount : 0u);
  }
}

TEST(HardCases, MicrobenchScenesHoldThePapersTriangleCountsAndLoadByName) {
  for (const std::string& name : benchmarkSceneNames()) {
    SCOPED_TRACE(name);
    const Scene s = makeBuiltinScene(name);
    EXPECT_EQ(s.triangleCount(), name == "microbench-144" ? 144u : name == "microbench-dense" ? 4096u : 262144u);
    EXPECT_EQ(s.name, name);
    EXPECT_EQ(degenerateCount(s), 0u);
    EXPECT_EQ(s.lights.size(), 1u);
    ASSERT_EQ(s.cameras.size(), 1u);
  }
}

TEST(HardCases, UnknownNameThrowsInputErrorListingTheValidNames) {
  try {
    makeBuiltinScene("sponza-typo");
    FAIL() << "no exception";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("sponza-typo"), std::string::npos);
    for (const std::string& name : builtinSceneNames()) EXPECT_NE(what.find(name), std::string::npos) << name;
    EXPECT_EQ(what.find('\n'), std::string::npos);
  }
}

TEST(HardCases, GrazingLightMeetsThePlaneAtNDotLOfOnePercent) {
  const Scene s = makeGrazing();
  const glm::dvec3 l = glm::normalize(glm::dvec3(s.lights[0].position));
  // The light position is rounded to float (relative error 2^-24 per component, ~500 m
  // magnitude): N.L = L.y changes by at most ~2 * 2^-24, far below 1e-6.
  EXPECT_NEAR(l.y, 0.01, 1e-6);
  EXPECT_GE(s.lights[0].range, glm::length(glm::dvec3(s.lights[0].position)));
}

TEST(HardCases, GrazingFarLightMeetsAPlaneFiveHundredMetresAwayAtNDotLOfOnePercent) {
  const Scene s = makeGrazingFar();
  const glm::dvec3 centre(0, 0, -kGrazingFarDepth), n = grazingFarNormal();
  const glm::dvec3 l = glm::normalize(glm::dvec3(s.lights[0].position) - centre);
  // The light position (~1000 m) is rounded to float: each component moves by at most 2^-24 of
  // 1000 m = 6e-5 m, which turns the 1000 m direction by under 1e-7; N.L within 1e-6.
  EXPECT_NEAR(glm::dot(l, n), 0.01, 1e-6);
  // Vertices are rounded to float: each component (|c| < 1024 m) by at most half an ulp, 2^-15 m,
  // which moves it off the plane by at most 2^-15 · (|n.x| + |n.y| + |n.z|) = 2^-15 · 1.366 = 4.2e-5 m.
  double minDist = 1e30;
  for (const Vertex& v : s.vertices) {
    EXPECT_NEAR(glm::dot(glm::dvec3(v.position) - centre, n), 0.0, std::ldexp(1.0, -15) * (n.x + n.y + n.z));
    minDist = std::min(minDist, glm::length(glm::dvec3(v.position)));
  }
  EXPECT_GT(minDist, 433.0);  // 500 · cos 30: every point is far beyond the 41.9 m where the constant t_min is safe
  EXPECT_NEAR(glm::length(eyeOf(s.cameras[0])), 0.0, 1e-6);
  // The light reaches the whole plane: its farthest corner is about 1735 m away.
  for (const Vertex& v : s.vertices)
    EXPECT_LT(glm::length(glm::dvec3(v.position) - glm::dvec3(s.lights[0].position)), s.lights[0].range);
}

TEST(HardCases, ThinGapOccluderFloatsOneMillimetreAboveTheReceiver) {
  const Scene s = makeThinGap();
  float lowestAboveZero = 1e30f;
  for (const Vertex& v : s.vertices)
    if (v.position.y > 0.0f) lowestAboveZero = std::min(lowestAboveZero, v.position.y);
  EXPECT_EQ(lowestAboveZero, float(kThinGap));
  EXPECT_LT(glm::length(eyeOf(s.cameras[0])), 1.0);  // near the camera
}

TEST(HardCases, FarOriginSceneLiesTenKilometresOut) {
  const Scene s = makeFarOrigin();
  glm::vec3 lo, hi;
  s.bounds(lo, hi);
  EXPECT_GE(lo.x, kFarOriginOffset - 4.0);
  EXPECT_LE(hi.x, kFarOriginOffset + 4.0);
  EXPECT_NEAR(eyeOf(s.cameras[0]).x, kFarOriginOffset + 3.0, 0.01);  // float view matrix: ~1 mm steps
  EXPECT_EQ(s.lights[0].position.x, float(kFarOriginOffset + 2.0));
}

TEST(HardCases, FarPlanesSitAtTheirDepthsInsideTheDepthRange) {
  const Scene s = makeFarPlanes();
  const Camera& c = s.cameras[0];
  std::vector<float> depths;
  for (const Vertex& v : s.vertices) {
    const float d = -v.position.z;
    if (std::find(depths.begin(), depths.end(), d) == depths.end()) depths.push_back(d);
  }
  ASSERT_EQ(depths.size(), 3u);
  for (double d : kFarPlaneDepths) {
    EXPECT_NE(std::find(depths.begin(), depths.end(), float(d)), depths.end()) << d;
    EXPECT_GT(d, c.znear);
    EXPECT_LT(d, c.zfar);
  }
}

TEST(HardCases, OpenOccluderIsOneDoubleSidedQuadSeenFromBehind) {
  const Scene s = makeOpenOccluder();
  int quads = 0;
  for (const Mesh& m : s.meshes)
    for (const Primitive& p : m.primitives)
      if (s.materials[p.material].doubleSided) {
        ++quads;
        EXPECT_EQ(p.indexCount, 6u);
        const glm::dvec3 n(s.vertices[p.vertexOffset].normal);
        const glm::dvec3 toEye = eyeOf(s.cameras[0]) - glm::dvec3(s.vertices[p.vertexOffset].position);
        EXPECT_LT(glm::dot(n, toEye), 0.0);  // the camera is behind the front face
        EXPECT_GT(glm::dot(n, glm::dvec3(s.lights[0].position) - glm::dvec3(s.vertices[p.vertexOffset].position)), 0.0);
      }
  EXPECT_EQ(quads, 1);
}

TEST(HardCases, TinyTrianglesAreUnderThreePixelsAndStripsOnePixelWide) {
  const Scene s = makeTinyTriangles();
  // Pixel footprint at 10 m for 1080 rows and yfov 60 degrees.
  const double pixel = 2 * 10 * std::tan(3.141592653589793 / 6) / 1080;
  const Primitive& p = s.meshes[0].primitives[0];
  uint32_t tiny = 0, strips = 0;
  for (uint32_t i = 0; i < p.indexCount; i += 3) {
    glm::dvec3 lo(1e30), hi(-1e30);
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3 v(s.vertices[p.vertexOffset + s.indices[p.firstIndex + i + k]].position);
      lo = glm::min(lo, v);
      hi = glm::max(hi, v);
    }
    const glm::dvec3 size = hi - lo;
    if (size.y < 3 * pixel) tiny += size.x < 3 * pixel;
    // float rounding of x near 3..8 m: 2^-21 m per coordinate, so the width is pixel +- 1e-6.
    else
      strips += std::abs(size.x - pixel) < 1e-6;
  }
  EXPECT_EQ(tiny, 1600u);
  EXPECT_EQ(strips, 20u);  // 10 strips of 2 triangles
}

}  // namespace
}  // namespace hb
