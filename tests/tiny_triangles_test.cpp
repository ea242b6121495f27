// Hard case (thesis 4.3.1: "artifacts do occur on triangles that are less than 3 pixels across"):
// a field of ~1.9 px triangles and 1-px strips against the sky. Reconstructed normals must be
// finite unit vectors or flagged as missing (exactly zero), never NaN; flagged exactly where the
// reconstruction has no neighbour to take a derivative from; and within the float rounding bound of
// the true normal where they are not.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "analysis/ray_analysis.h"
#include "base/numbers.h"
#include "effects/shadows/shadows_part.h"
#include "frame/renderer.h"
#include "gpu_fixture.h"
#include "reference/reconstruct_ref.h"
#include "scene/hard_cases.h"
#include "shared/gpu_types.h"

namespace hb {
namespace {

class ShadowTinyTriangles : public testing::GpuTest {};

// An analysis frame of the tiny-triangles scene at w x h, 16x16 tiles, with the given normals.
RenderSettings tinySettings(uint32_t w, uint32_t h, NormalCulling normals) {
  RenderSettings s;
  s.width = w;
  s.height = h;
  s.tileSize = 16;
  s.normals = normals;
  return s;
}

// The bound on a reconstructed normal's error here, from the triangles' size and float rounding.
//  - Geometry: every triangle and strip lies in the one plane z = −10 (hard_cases.cpp: float
//    vertices whose z is exactly −10), parallel to the image of a camera at the origin looking
//    down −z; its normal, facing the eye, is +z. The triangles' legs are 2 cm = 1.87 px and they are
//    10 cm = 9.35 px apart; the strips are 1 px wide and 0.5 m apart. So the samples a derivative
//    takes (surface.glsl.inc derivative(): naive the ±1 neighbour, improved the ±1 and ±2 ones)
//    are on the pixel's own triangle or strip or are sky, and every sample with depth is on the
//    plane: no derivative crosses a depth edge, whatever the method.
//  - What the size decides is whether a pixel gets a normal: derivative() fails, for both methods,
//    exactly when neither the −1 nor the +1 neighbour along x (or along y) has depth, and then the
//    normal is flagged (exactly zero; its rays are traced). A 1.9-px triangle covers one or two
//    centres per row and column, a 1-px strip one per row, so most pixels are flagged.
//  - What remains is rounding, as on a plane seen head-on (ShadowNormals in shadow_reconstruction_gpu_test.cpp,
//    docs/numerics.md): each position errs by ε_P·r, ε_P = 16u (the rasterised depth) + 8u (Alg. 4.1
//    in float), r the distance to the eye; a derivative (two positions one pixel apart) by 2ε_P·r
//    against its length s = 10 m · 2 tan(30°) / 1080 = 1.07 cm (the pixel's footprint on the
//    plane); dx ⟂ dy, each turns by <= 2ε_P·r/s, so n = dx × dy turns by <= 4ε_P·r/s (first order):
//    0.29° at r = 10 m, 0.39° at the farthest strip (r = 12.7 m). (lavapipe gives exactly +z: a
//    plane of constant depth rasterises to one depth value, so every derivative's z is exactly 0.)
double tinyNormalBoundRad(double r, const Camera& cam, uint32_t height) {
  const double epsP = 16.0 * kU + 8.0 * kU;
  const double s = 10.0 * 2.0 * std::tan(double(cam.yfov) / 2.0) / double(height);
  return 4.0 * epsP * r / s;
}

TEST_F(ShadowTinyTriangles, NormalsAreUnitOrFlaggedAndWithinTheRoundingBoundOfThePlane) {
  const Scene scene = makeBuiltinScene("tiny-triangles");
  const Bvh bvh = buildBvh(scene);
  const glm::dvec3 planeNormal(0.0, 0.0, 1.0), eye(0.0);
  for (NormalCulling method : {NormalCulling::Naive, NormalCulling::Improved}) {
    const char* name = method == NormalCulling::Naive ? "naive" : "improved";
    // The scene's triangles are ~1.9 px wide at 1920x1080 (hard_cases.h).
    const RenderSettings s = tinySettings(1920, 1080, method);
    Renderer renderer(*ctx, scene, s);
    renderer.renderFrame(true);
    const std::vector<float> depth = renderer.readDepth();
    const ShadowReadback sh = shadowsOf(renderer)->readShadows();
    auto hasDepth = [&](int x, int y) {
      return x >= 0 && y >= 0 && x < int(s.width) && y < int(s.height) && depth[size_t(y) * s.width + x] > 0.0f;
    };
    uint64_t unit = 0, flagged = 0, bad = 0, wrongFlag = 0, beyond = 0;
    double worstRatio = 0.0, worstDeg = 0.0;
    for (int y = 0; y < int(s.height); ++y)
      for (int x = 0; x < int(s.width); ++x) {
        const size_t i = size_t(y) * s.width + x;
        if (!hasDepth(x, y)) continue;
        const float* n = &sh.normals[4 * i];
        const double len = std::sqrt(double(n[0]) * n[0] + double(n[1]) * n[1] + double(n[2]) * n[2]);
        const bool expectNormal =
            (hasDepth(x - 1, y) || hasDepth(x + 1, y)) && (hasDepth(x, y - 1) || hasDepth(x, y + 1));
        // A normalised float vector has |n| within a few u of 1: 1e-5 is ~170 u, generous on purpose
        // (this count is about NaN and garbage; the angle below is about the last bits).
        if (std::isfinite(len) && std::abs(len - 1.0) < 1e-5) {
          ++unit;
          wrongFlag += !expectNormal;
          const glm::dvec3 g = glm::dvec3(n[0], n[1], n[2]) / len;
          const double angle = std::atan2(glm::length(glm::cross(g, planeNormal)), glm::dot(g, planeNormal));
          const glm::dvec3 p(sh.positions[4 * i], sh.positions[4 * i + 1], sh.positions[4 * i + 2]);
          const double bound = tinyNormalBoundRad(glm::length(p - eye), scene.cameras[0], s.height);
          beyond += angle > bound;
          worstRatio = std::max(worstRatio, angle / bound);
          worstDeg = std::max(worstDeg, angle * 180.0 / kPi);
        } else if (n[0] == 0.0f && n[1] == 0.0f && n[2] == 0.0f) {
          ++flagged;
          wrongFlag += expectNormal;
        } else {
          ++bad;
        }
      }
    const auto cam =
        reconstructionCamera<double>(glm::dmat4(renderer.view()), glm::dmat4(renderer.proj()), s.width, s.height);
    const NormalAccuracy acc = normalAccuracy(sh.normals, referenceSurface(bvh, depth, cam));
    std::printf(
        "tiny triangles, %s normals: %llu unit, %llu flagged, %llu flagged against the neighbour rule; against "
        "+z: max %.4f deg, max angle / bound %.3g, %llu beyond; against the double ray cast's surface (%llu "
        "compared, %llu without one): mean %.4f deg, p95 %.4f deg\n",
        name, (unsigned long long)unit, (unsigned long long)flagged, (unsigned long long)wrongFlag, worstDeg,
        worstRatio, (unsigned long long)beyond, (unsigned long long)acc.compared,
        (unsigned long long)acc.withoutReference, acc.meanAngleDeg, acc.p95AngleDeg);
    EXPECT_EQ(bad, 0u) << name;
    EXPECT_GT(unit, 0u) << name;
    EXPECT_EQ(wrongFlag, 0u) << name << ": pixels flagged (or not) against derivative()'s rule";
    EXPECT_EQ(beyond, 0u) << name << ": normals farther from the plane's than the rounding bound";
    // The true surface (the double ray cast) is the plane wherever it is found: its normal is +z, so
    // the bound holds against it too.
    EXPECT_LE(acc.maxAngleDeg, tinyNormalBoundRad(13.0, scene.cameras[0], s.height) * 180.0 / kPi) << name;
  }
}

// Hard case "sky pixels at odd and even widths": the tiny-triangles scene is mostly sky. At an odd
// and an even size (the odd width puts a pixel centre exactly on ndc.x = 0), every sky pixel gets
// no position, no normal, no ray and an empty mask; every other pixel's position and normal are
// finite; the colour image has no NaN/Inf; and a tile with no geometry lists no light.
TEST_F(ShadowTinyTriangles, SkyPixelsAtOddAndEvenWidthsGetNoPositionNoRayNoNaN) {
  const Scene scene = makeBuiltinScene("tiny-triangles");
  for (auto [w, h] : {std::pair<uint32_t, uint32_t>{321, 181}, {320, 180}}) {
    for (NormalCulling method : {NormalCulling::Off, NormalCulling::Improved}) {
      const RenderSettings s = tinySettings(w, h, method);
      Renderer renderer(*ctx, scene, s);
      renderer.renderFrame(true);
      const std::vector<float> depth = renderer.readDepth();
      const ShadowReadback sh = shadowsOf(renderer)->readShadows();
      const CullingReadback cull = renderer.readCulling();
      const std::vector<float> color = renderer.readColor();
      uint64_t sky = 0, skyWithSomething = 0, surface = 0, nonFinite = 0;
      for (size_t i = 0; i < depth.size(); ++i) {
        const float* p = &sh.positions[4 * i];
        const float* n = &sh.normals[4 * i];
        for (int c = 0; c < 4; ++c)
          nonFinite += !std::isfinite(p[c]) + !std::isfinite(n[c]) + !std::isfinite(color[4 * i + c]);
        if (depth[i] > 0.0f) {
          ++surface;
          continue;
        }
        ++sky;
        skyWithSomething += sh.visibility[i] != 0u || sh.accounting[4 * i] != 0u || sh.accounting[4 * i + 1] != 0u ||
                            sh.accounting[4 * i + 2] != 0u || p[0] != 0.0f || p[1] != 0.0f || p[2] != 0.0f ||
                            p[3] != 0.0f || n[0] != 0.0f || n[1] != 0.0f || n[2] != 0.0f;
      }
      uint64_t emptyTiles = 0, emptyTilesWithLights = 0;
      for (uint32_t ty = 0; ty < cull.tilesY; ++ty)
        for (uint32_t tx = 0; tx < cull.tilesX; ++tx) {
          bool any = false;
          const uint32_t t = s.tileSize;
          for (uint32_t y = ty * t; y < std::min(h, ty * t + t) && !any; ++y)
            for (uint32_t x = tx * t; x < std::min(w, tx * t + t) && !any; ++x) any = depth[size_t(y) * w + x] > 0.0f;
          if (any) continue;
          ++emptyTiles;
          emptyTilesWithLights += cull.count[ty * cull.tilesX + tx] != 0u;
        }
      const std::string what = std::to_string(w) + "x" + std::to_string(h) + " normals=" + toString(method);
      EXPECT_GT(sky, depth.size() / 2) << what;  // the case is about sky: most of the image
      EXPECT_GT(surface, 0u) << what;
      EXPECT_EQ(skyWithSomething, 0u) << what << ": sky pixels with a position, normal, ray or mask bit";
      EXPECT_EQ(nonFinite, 0u) << what << ": NaN/Inf in positions, normals or colour";
      EXPECT_GT(emptyTiles, 0u) << what;
      EXPECT_EQ(emptyTilesWithLights, 0u) << what << ": tiles without geometry that list a light";
    }
  }
}

}  // namespace
}  // namespace hb
