// The frame on top of 3D rasterization (primary=3dr) on the real device: the atrium's ids and depths
// against a double-precision ray cast (at the origin and 10 km from it), geometric normals and hit
// positions, visibility-buffer shading against the forward pass, the early depth test, the
// hardware prepass's depth, and the timing of each dispatch.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "analysis/primary_analysis.h"
#include "base/errors.h"
#include "base/image_io.h"
#include "effects/shadows/shadows_part.h"
#include "raster3d_test_scenes.h"
#include "reference/flip.h"
#include "scene/atrium.h"
#include "scene/hard_cases.h"

namespace hb::raster3d_test {
namespace {

TEST_F(Raster3dTest, AtriumIdsAndDepthsMatchADoublePrecisionRayCast) {
  // Every pixel against the watertight double ray cast along the same rays (primary_analysis.h):
  // ids equal wherever both hit, except at ties (a ray within kTieMargin of an edge, or touching
  // surfaces); holes and spurious hits likewise only at ties; depth within 1e-6 at p99.9 (t comes
  // from two float dot products: a few u unless the ray grazes the plane).
  const Scene scene = makeAtrium(AtriumParams{});
  RenderSettings rs = atrium3drSettings();
  Renderer r(*ctx, scene, rs);
  r.renderFrame(true);
  const PrimaryComparison c =
      comparePrimary(buildBvh(scene), r.raster3d()->readVisibility(), raster3dConstants(r.camera(), 160, 90, 0, 0));
  std::printf(
      "atrium 160x90 vs ray cast: %llu both hit, %llu ids equal, %llu mismatches, %llu holes, %llu spurious, "
      "%llu not ties, depth p99.9 %.3g, max %.3g\n",
      (unsigned long long)c.bothHit, (unsigned long long)c.idsEqual, (unsigned long long)c.idMismatches,
      (unsigned long long)c.holes, (unsigned long long)c.spurious, (unsigned long long)c.notTies, c.depthRelP999,
      c.depthRelMax);
  EXPECT_GT(c.bothHit, 10000u);
  EXPECT_EQ(c.notTies, 0u);
  // The per-pixel test counts (edge_evaluations.png) add up to the frame's counter.
  uint64_t tests = 0;
  for (uint32_t n : r.raster3d()->readPixelTests()) tests += n;
  EXPECT_EQ(tests, r.raster3d()->readCounters().pixelsTested);
  EXPECT_GE(double(c.idsEqual), 0.999 * double(c.bothHit));
  EXPECT_LE(c.depthRelP999, 1e-6);
}

// far-origin: the cube scene 10 km from the world origin, where float spacing is ~1 mm. 3DR sets a
// triangle up from eye-relative vertices (raster3d.glsl.inc r3dRelative: world − eye in float,
// exact by Sterbenz where a coordinate of both lies within a factor 2 of the other, as the 10 km
// one does; the small ones round by u of their difference), so its edge functions see the same
// metre-scale numbers as at the origin. The bounds: ids equal on >= 99.999 % of the pixels
// both hit (at 320x180 no pixel may differ unless a tie), depth p99.9 <= 1e-6, 0 that are not ties;
// the same cube at the origin gives the comparison's baseline.
TEST_F(Raster3dTest, FarFromTheOriginTheCameraRelativeSetupMatchesTheDoubleRayCast) {
  for (const Scene& scene : {makeFarOrigin(), makeCube({0, 0, 0})}) {
    SCOPED_TRACE(scene.name);
    RenderSettings rs;
    rs.width = 320;
    rs.height = 180;
    rs.primary = hb::testing::primaryNamed("3dr");
    Renderer r(*ctx, scene, rs);
    r.renderFrame(true);
    const PrimaryComparison c = comparePrimary(buildBvh(scene), r.raster3d()->readVisibility(),
                                               raster3dConstants(r.camera(), rs.width, rs.height, 0, 0));
    std::printf(
        "%s 320x180 vs ray cast: %llu both hit, %llu ids equal, %llu holes, %llu spurious, %llu not ties, "
        "depth p99.9 %.3g, max %.3g\n",
        scene.name.c_str(), (unsigned long long)c.bothHit, (unsigned long long)c.idsEqual, (unsigned long long)c.holes,
        (unsigned long long)c.spurious, (unsigned long long)c.notTies, c.depthRelP999, c.depthRelMax);
    EXPECT_GT(c.bothHit, 20000u);
    EXPECT_EQ(c.notTies, 0u);
    EXPECT_GE(double(c.idsEqual), 0.99999 * double(c.bothHit));
    EXPECT_LE(c.depthRelP999, 1e-6);
  }
}

TEST_F(Raster3dTest, GeometricNormalsAreTheVisibleTrianglesOwnAndHitPositionsNeed3dr) {
  // normal_culling=geometric reads the triangle the visibility buffer names: its normal must be the
  // shading pass's reference normal of that pixel (the same triangle's face normal, computed there
  // from the drawn vertices: both are float cross products, so within a few u; 1e-4 rad allows
  // triangles 100x longer than wide).
  const Scene scene = makeAtrium(AtriumParams{});
  RenderSettings rs = atrium3drSettings();
  rs.normals = NormalCulling::Geometric;
  rs.worldPos = WorldPosMethod::Hit;
  Renderer r(*ctx, scene, rs);
  r.renderFrame(true);
  const ShadowReadback sh = shadowsOf(r)->readShadows();
  const std::vector<float> ref = r.readRefNormals();
  size_t compared = 0, off = 0;
  for (size_t i = 0; i < ref.size() / 4; ++i) {
    if (ref[4 * i + 3] != 1.0f) continue;
    const glm::dvec3 a(sh.normals[4 * i], sh.normals[4 * i + 1], sh.normals[4 * i + 2]);
    const glm::dvec3 b(ref[4 * i], ref[4 * i + 1], ref[4 * i + 2]);
    if (glm::dot(a, a) == 0.0) continue;  // degenerate: no normal, no culling
    ++compared;
    off += std::acos(std::clamp(glm::dot(a, b) / (glm::length(a) * glm::length(b)), -1.0, 1.0)) > 1e-4;
  }
  EXPECT_GT(compared, 10000u);
  EXPECT_EQ(off, 0u);
  RenderSettings hw = rs;
  hw.primary = hb::testing::primaryNamed("hardware");
  EXPECT_THROW(Renderer(*ctx, scene, hw), InputError);
}

TEST_F(Raster3dTest, VisbufferShadingMatchesTheForwardPass) {
  // shading=visbuffer shades the same triangle per pixel as the forward pass on top of 3dr, with
  // the same BRDF (shading_brdf.glsl.inc); it differs only where texture LOD comes from analytic
  // derivatives instead of 2x2-quad differences and in the order of float interpolation. So the
  // face normals (same triangle, same float ops) agree to rounding everywhere, and the image's
  // FLIP mean stays below 0.05 (the FLIP paper's threshold of a barely noticeable difference).
  AtriumParams ap;
  const Scene scene = makeAtrium(ap);
  auto renderWith = [&](bool visbuffer, std::vector<float>& normals) {
    RenderSettings rs;
    rs.width = 160;
    rs.height = 90;
    rs.primary = hb::testing::primaryNamed("3dr");
    rs.shading = (visbuffer) ? ShadingMethod::Visbuffer : ShadingMethod::Forward;
    Renderer r(*ctx, scene, rs);
    r.renderFrame(true);
    normals = r.readRefNormals();
    ImageF hdr{160, 90, 4, r.readColor()};
    return toneMapToSrgb(hdr, 0.0f, ToneMapOperator::AcesFitted).image;
  };
  std::vector<float> nForward, nVisbuffer;
  const ImageRGBA8 forward = renderWith(false, nForward), visbuffer = renderWith(true, nVisbuffer);
  // Where the hardware rasterizer's fill rule gives an edge pixel to the neighbouring triangle,
  // the forward pass has no fragment of the 3DR triangle there and leaves the pixel unshaded: the
  // visibility-buffer pass shades it. Those are counted, not compared.
  size_t valid = 0, normalsOff = 0, forwardMissed = 0;
  for (size_t i = 0; i < nForward.size() / 4; ++i) {
    if (nForward[4 * i + 3] != nVisbuffer[4 * i + 3]) {
      forwardMissed += nForward[4 * i + 3] == 0.0f && nVisbuffer[4 * i + 3] == 1.0f;
      normalsOff += !(nForward[4 * i + 3] == 0.0f && nVisbuffer[4 * i + 3] == 1.0f);
      continue;
    }
    if (nForward[4 * i + 3] != 1.0f) continue;
    ++valid;
    const glm::dvec3 a(nForward[4 * i], nForward[4 * i + 1], nForward[4 * i + 2]);
    const glm::dvec3 b(nVisbuffer[4 * i], nVisbuffer[4 * i + 1], nVisbuffer[4 * i + 2]);
    normalsOff += glm::length(a - b) > 1e-5;
  }
  const FlipResult flip = ldrFlip(forward, visbuffer);
  std::printf(
      "visbuffer vs forward shading (atrium 160x90): FLIP mean %.5f, p95 %.5f; %zu of %zu normals differ; "
      "%zu pixels the forward pass left unshaded\n",
      flip.mean, flip.p95, normalsOff, valid, forwardMissed);
  EXPECT_GT(valid, 10000u);
  EXPECT_EQ(normalsOff, 0u);
  EXPECT_LE(forwardMissed, valid / 100);
  EXPECT_LT(flip.mean, 0.05);
  RenderSettings hw;
  hw.shading = ShadingMethod::Visbuffer;
  EXPECT_THROW(Renderer(*ctx, scene, hw), InputError);
}

TEST_F(Raster3dTest, WithVisbufferShadingTheResolveWritesTheDepthImageItselfBitForBitAsTheCopy) {
  // No pass draws against the depth of a compute primary with visbuffer shading, so the frame's
  // depth is an R32F colour image that the resolve writes itself (renderer.cpp frameDepth); forward
  // shading tests depth in a draw, so there it stays a D32 image filled by a copy of the resolved
  // buffer. The floats are the same, so the depth, the light lists built from it and the shadow
  // pass that reconstructs positions from it (world_pos alg41) are the same bit for bit.
  const Scene scene = makeAtrium(AtriumParams{});
  struct Out {
    std::vector<float> depth;
    std::vector<uint32_t> lists, shadows;
    std::string format;
    std::vector<std::string> subPasses;
  };
  auto renderWith = [&](ShadingMethod shading) {
    RenderSettings rs;
    rs.width = 160;
    rs.height = 90;
    rs.primary = hb::testing::primaryNamed("3dr-binned");
    rs.shading = shading;
    rs.worldPos = WorldPosMethod::Alg41;
    Renderer r(*ctx, scene, rs);
    r.renderFrame(true);
    const CullingReadback c = r.readCulling();
    std::vector<uint32_t> lists;  // each tile's count and lights (the slots past a tile's count are not written)
    for (size_t t = 0; t < c.count.size(); ++t) {
      lists.push_back(c.count[t]);
      lists.insert(lists.end(), c.indices.begin() + c.offset[t], c.indices.begin() + c.offset[t] + c.count[t]);
    }
    return Out{r.readDepth(), lists, shadowsOf(r)->readShadows().visibility,
               r.resources().toJson()["depth"]["format"].get<std::string>(), r.raster3d()->subPasses()};
  };
  const Out copied = renderWith(ShadingMethod::Forward), direct = renderWith(ShadingMethod::Visbuffer);
  EXPECT_NE(copied.format.find("D32_SFLOAT"), std::string::npos) << copied.format;
  EXPECT_NE(direct.format.find("R32_SFLOAT"), std::string::npos) << direct.format;
  auto has = [](const std::vector<std::string>& v, const char* s) {
    return std::find(v.begin(), v.end(), s) != v.end();
  };
  EXPECT_TRUE(has(copied.subPasses, "raster3d.depth_copy"));
  EXPECT_FALSE(has(direct.subPasses, "raster3d.depth_copy"));
  ASSERT_EQ(copied.depth.size(), size_t(160) * 90);
  size_t covered = 0;
  for (float d : copied.depth) covered += d > 0.0f;
  EXPECT_GT(covered, 10000u);  // the atrium fills most of the view: a depth worth comparing
  EXPECT_EQ(std::memcmp(copied.depth.data(), direct.depth.data(), copied.depth.size() * sizeof(float)), 0);
  EXPECT_EQ(copied.lists, direct.lists);
  EXPECT_EQ(copied.shadows, direct.shadows);
}

TEST_F(Raster3dTest, On3drEarlyDepthTestShadesExactlyWhatTheIdTestAloneShades) {
  // The shading pass on top of 3dr keeps a fragment when its triangle is the pixel's; the biased
  // early depth test in front of that must never remove the visible one. Same image, bit for bit.
  AtriumParams ap;
  const Scene scene = makeAtrium(ap);
  auto colorOf = [&](bool depthTest) {
    RenderSettings rs;
    rs.width = 160;
    rs.height = 90;
    rs.primary = hb::testing::primaryNamed("3dr");
    rs.raster3dShadingDepthTest = depthTest;
    Renderer r(*ctx, scene, rs);
    r.renderFrame(false);
    return r.readColor();
  };
  const std::vector<float> withTest = colorOf(true), idOnly = colorOf(false);
  ASSERT_EQ(withTest.size(), idOnly.size());
  size_t differ = 0, lit = 0;
  for (size_t i = 0; i < withTest.size(); i += 4) {
    differ += withTest[i] != idOnly[i] || withTest[i + 1] != idOnly[i + 1] || withTest[i + 2] != idOnly[i + 2];
    lit += idOnly[i] + idOnly[i + 1] + idOnly[i + 2] > 0.0f;
  }
  EXPECT_GT(lit, 5000u);
  EXPECT_EQ(differ, 0u);
}

TEST_F(Raster3dTest, AtriumFrameOnTopOf3drMatchesTheHardwarePrepassDepth) {
  AtriumParams ap;
  const Scene scene = makeAtrium(ap);
  auto depthOf = [&](const char* primary) {
    RenderSettings rs;
    rs.width = 160;
    rs.height = 90;
    rs.primary = hb::testing::primaryNamed(primary);
    Renderer r(*ctx, scene, rs);
    r.renderFrame(true);
    return r.readDepth();
  };
  const std::vector<float> hw = depthOf("hardware"), r3 = depthOf("3dr");
  // Both rasterizers compute the same depth of the same nearest surface up to rounding: relative
  // differences of a few u (2^-24) except where the two fill rules pick different triangles on an
  // edge, or a surface behind is within rounding of the front. Require 99 % within 1e-4.
  size_t both = 0, close = 0, skyMismatch = 0;
  for (size_t i = 0; i < hw.size(); ++i) {
    if ((hw[i] == 0.0f) != (r3[i] == 0.0f)) ++skyMismatch;
    if (hw[i] == 0.0f || r3[i] == 0.0f) continue;
    ++both;
    close += std::abs(double(hw[i]) - r3[i]) <= 1e-4 * std::abs(double(hw[i]));
  }
  EXPECT_GT(both, 10000u);
  EXPECT_GE(double(close), 0.99 * double(both));
  EXPECT_LE(skyMismatch, hw.size() / 1000);
}

TEST_F(Raster3dTest, EachDispatchIsTimedInsideItsPass) {
  const Scene scene = makeAtrium(AtriumParams{});
  for (const char* primary : {"3dr", "3dr-binned", "raycast"}) {
    RenderSettings rs = atrium3drSettings();
    rs.primary = hb::testing::primaryNamed(primary);
    rs.effects.add(EffectSource::Config, "test", {{"shadows", false}});
    Renderer r(*ctx, scene, rs);
    const FrameTiming t = r.renderFrame(false);
    std::vector<std::string> names;
    for (const auto& [name, ms] : t.passMs) names.push_back(name);
    const std::string pass = std::string(primary) == "raycast" ? "raycast" : "raster3d";
    std::vector<std::string> expected = {pass};
    if (pass == "raster3d") expected.push_back("raster3d.triangles");
    if (std::string(primary) == "3dr-binned")
      for (const char* sub : {"raster3d.count", "raster3d.scan", "raster3d.fill"}) expected.push_back(sub);
    if (pass == "raster3d") expected.push_back("raster3d.tiles");
    expected.push_back(pass + ".resolve");
    expected.push_back(pass + ".depth_copy");
    expected.push_back("light_culling");
    expected.push_back("shading");
    EXPECT_EQ(names, expected) << primary;
  }
}

}  // namespace
}  // namespace hb::raster3d_test
