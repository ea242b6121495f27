// Ambient occlusion on the real device (effects/ambient_occlusion/ao_pass.h, effects/ambient_occlusion/ao_effect.h):
// the LDM lists against the exact CPU LDM (reference/ldm_ref.h), the ray-traced AO against the
// CPU's double ray tracing from the GPU's own positions and normals, open sky and a closed box,
// the LDM approximation's error on the atrium within the issue's bounds, determinism under a
// shuffled draw order, and nothing built when the effect does not run.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "effects/ambient_occlusion/ao_analysis.h"
#include "effects/ambient_occlusion/ao_part.h"
#include "effects/shadows/shadows_part.h"
#include "frame/renderer.h"
#include "gpu_fixture.h"
#include "reference/eq_partition.h"
#include "reference/ldm_ref.h"
#include "scene/atrium.h"
#include "scene/camera.h"
#include "scene/mesh_builder.h"

namespace hb {
namespace {

RenderSettings aoSettings(uint32_t w, uint32_t h, const nlohmann::json& ao, bool shadows = true) {
  return testing::settingsWithEffects(w, h, {{"shadows", shadows}, {"ambient_occlusion", ao}});
}

using testing::lookFrom;

// One mesh (filled by `build`), a point light, a camera and a white ambient term.
Scene aoScene(const char* name, const std::function<void(MeshBuilder&)>& build, glm::vec3 light, const Camera& camera) {
  Scene s;
  s.name = name;
  s.materials.push_back({});
  MeshBuilder mb(name);
  build(mb);
  mb.appendTo(s);
  Light l;
  l.position = light;
  l.intensity = 20.0f;
  l.range = 30.0f;
  s.lights.push_back(l);
  s.cameras.push_back(camera);
  s.ambient = Ambient{{1, 1, 1}, 0.5f};
  return s;
}

// A ground quad of side 40 m at y = 0, seen from 3 m above: every visible point sees open sky.
Scene openSky() {
  return aoScene(
      "open-sky",
      [](MeshBuilder& mb) {
        addQuad(mb, 0, {-20, 0, -20}, {20, 0, -20}, {20, 0, 20}, {-20, 0, 20}, {0, 1, 0});
      },
      {0, 5, 0}, lookFrom({0, 3, 4}, {0, 0, -2}));
}

// A closed box 4 x 3 x 5 m with the camera (and the light) inside: nothing inside sees the sky.
Scene closedBox() {
  return aoScene(
      "closed-box",
      [](MeshBuilder& mb) {
        addBox(mb, 0, {-2, 0, -2.5}, {2, 3, 2.5});
      },
      {0, 2.5, 0}, lookFrom({0.3f, 1.5f, 2.0f}, {-0.5f, 1.0f, -2.5f}));
}

std::vector<float> aoOf(const VulkanContext& ctx, const Scene& scene, const RenderSettings& rs) {
  Renderer r(ctx, scene, rs);
  r.renderFrame(true);
  return aoPassOf(r)->readAo();
}

class AoGpuTest : public testing::GpuTest {};

// The GPU's lists against the exact LDM through the same pixel lines (the maps' float parameters
// taken as they are): the issue asks >= 99.5 % of pixels equal, depths within 1e-4 m. A list may
// differ where the line passes within rounding of an edge (the rasterizer's fill rule against the
// watertight cast, ldm_ref.h) or two surfaces lie within 1e-9·2r of each other (merged on the CPU).
TEST_F(AoGpuTest, LdmListsEqualTheExactLdmThroughTheSamePixelLines) {
  const Scene scene = makeAtrium(AtriumParams{});
  const Bvh bvh = buildBvh(scene);
  for (const char* build : {"hardware", "3dr"})
    for (const char* list : {"max64", "cas", "sbuffer"}) {
      SCOPED_TRACE(std::string(build) + ", " + list);
      Renderer r(
          *ctx, scene,
          aoSettings(64, 36, {{"directions", 8}, {"ldm_resolution", 128}, {"ldm_build", build}, {"ldm_list", list}}));
      r.renderFrame(true);
      const LdmBuild& ldm = *aoPassOf(r)->ldm();
      const std::vector<std::vector<float>> lists = ldm.readLists();
      const LdmCounters counters = ldm.readCounters();
      EXPECT_EQ(counters.overflow, 0u);
      EXPECT_EQ(counters.unfinished, 0u);
      const uint32_t R = ldm.resolution();
      size_t pixels = 0, equal = 0, nodes = 0;
      double worst = 0;
      for (uint32_t m = 0; m < ldm.mapCount(); ++m) {
        const gpu::LdmMap& g = ldm.maps()[m];
        const LdmView view{glm::dvec3(g.dir),          glm::dvec3(g.right),      glm::dvec3(g.up),
                           glm::dvec3(g.centreRadius), double(g.centreRadius.w), R};
        const ExactLdm exact = exactLdm(bvh, view);
        for (uint32_t j = 0; j < R; ++j)
          for (uint32_t i = 0; i < R; ++i) {
            const std::span<const double> want = exact.pixel(i, j);
            const std::vector<float>& got = lists[(size_t(m) * R + j) * R + i];
            ++pixels;
            nodes += got.size();
            bool same = want.size() == got.size();
            for (size_t k = 0; same && k < got.size(); ++k) {
              const double d = std::abs(double(got[k]) - want[k]);
              same = d <= 1e-4;
              worst = std::max(worst, d);
            }
            equal += same;
          }
      }
      std::printf(
          "atrium LDMs (%s, %s), 8 maps of 128x128: %zu of %zu pixel lists equal the exact ones (%.4f %%), %zu "
          "nodes, largest depth difference of equal-length lists %.3g m\n",
          build, list, equal, pixels, 100.0 * double(equal) / double(pixels), nodes, worst);
      EXPECT_EQ(nodes, counters.allocated);
      EXPECT_GE(double(equal), 0.995 * double(pixels));
    }
}

// Open sky: nothing but the ground, so every direction of n's hemisphere is free and AO is the
// quadrature (2/N)·Σ|n·v_i| of the cosine integral, 1 within 1.2 % at N = 64 (eq_partition_test:
// 1.035 % over random normals). ldm and raytraced give it up to the float sum (N terms: 64u), the
// reference exactly 1. hbao sees only the ground, whose samples rise above x's tangent plane by
// their positions' rounding alone (4u·d each, d <= 8 m from the eye, over r >= 1 pixel ≈ 0.03 m):
// sin h <= 2·4u·8/0.03 ≈ 1.3e-4 per direction, so AO >= 1 − 1.3e-4.
// gtao under open sky integrates the unoccluded slice in closed form, exactly 1 over all slice
// angles about the view vector; N = 64 evenly rotated slices (the default directions) leave a
// quadrature error that a double evaluation of the same formula bounds by 9.79e-5 over normals
// (src/effects/ambient_occlusion/gtao_quadrature_test.cpp prints it and holds it to this constant)
// tilted up to 89.5 degrees from the view vector (any azimuth, view vectors up to 60 degrees off
// the axis, three rotations); the ground's samples add hbao's rounding (1.3e-4 in a horizon's
// sine, above) on each side of a slice.
constexpr double kGtaoQuadrature64 = 1.0e-4;  // computed: 9.79e-5, rounded up
constexpr double kGtaoOpenSky = kGtaoQuadrature64 + 2 * 1.3e-4;

TEST_F(AoGpuTest, UnderOpenSkyAoIsTheDirectionQuadratureOfOne) {
  const Scene scene = openSky();
  const std::vector<glm::dvec3> dirs = ldmDirections(64);
  double quadrature = 0;
  for (const glm::dvec3& v : dirs) quadrature += std::abs(v.y);
  quadrature *= 2.0 / 64.0;
  EXPECT_NEAR(quadrature, 1.0, 0.012);
  for (const char* method : {"ldm", "raytraced", "reference", "hbao", "gtao"}) {
    SCOPED_TRACE(method);
    const std::vector<float> ao =
        aoOf(*ctx, scene, aoSettings(48, 32, {{"method", method}, {"samples", 64}, {"steps", 8}}));
    const std::string m = method;
    const double expected = m == "ldm" || m == "raytraced" ? quadrature : 1.0;
    const double tolerance = m == "hbao" ? 1.3e-4 : m == "gtao" ? kGtaoOpenSky : 64.0 * 5.96e-8;
    size_t ground = 0, off = 0;
    double worst = 0;
    for (float a : ao) {
      if (a < 0.0f) continue;
      ++ground;
      off += std::abs(a - expected) > tolerance;
      worst = std::max(worst, std::abs(a - expected));
    }
    std::printf("open sky, %s: %zu ground pixels, largest |AO - %.6f| = %.3g (tolerance %.3g)\n", method, ground,
                expected, worst, tolerance);
    EXPECT_GT(ground, 1000u);
    EXPECT_EQ(off, 0u);
  }
}

// Inside a closed box every ray meets a wall: the ray tracer's AO is 0 at every point whose
// position and normal are its face's (points on a crease take a neighbour's depth sample, and a
// rounding may put them a fraction of a millimetre outside: AO there counts rays that leave
// through the wall they start on). So only points at least 0.5 m from every other face count
// (the improved normal reads ±2 pixels, ~0.25 m here). The LDM also misses a wall nearer than its
// bias along a direction (ao_common.glsl.inc): (√2/2)·(2r/R)·tan θ > 0.5 m with 2r/R = 7.07/64 m
// needs tan θ > 6.4, cos θ = c < 0.155; a share ~c of the N directions has |n·v| < c, each
// weighing 2|n·v|/N, so such points keep AO <= 2c² = 0.048. A traced ray that grazes its own wall
// (|n·v| below ~1e-3, running within rounding of the wall into the crease ahead) may slip through
// that crease: it weighs 2|n·v|/N < 1e-4 (measured: 1.9e-6 once, on lavapipe).
TEST_F(AoGpuTest, InsideAClosedBoxNothingSeesTheSky) {
  const Scene scene = closedBox();
  const glm::vec3 lo(-2, 0, -2.5), hi(2, 3, 2.5);
  for (const char* method : {"raytraced", "reference", "ldm"}) {
    SCOPED_TRACE(method);
    RenderSettings rs = aoSettings(48, 32, {{"method", method}, {"samples", 64}, {"ldm_resolution", 64}});
    Renderer r(*ctx, scene, rs);
    r.renderFrame(true);
    const std::vector<float> ao = aoPassOf(r)->readAo();
    const ShadowReadback sh = shadowsOf(r)->readShadows();
    size_t inside = 0, interior = 0;
    double worst = 0;
    for (size_t i = 0; i < ao.size(); ++i) {
      if (ao[i] < 0.0f) continue;
      ++inside;
      const glm::vec3 p(sh.positions[4 * i], sh.positions[4 * i + 1], sh.positions[4 * i + 2]);
      // Distances to the six faces: the nearest is the point's own; the next must be >= 0.5 m.
      std::vector<float> d = {p.x - lo.x, hi.x - p.x, p.y - lo.y, hi.y - p.y, p.z - lo.z, hi.z - p.z};
      for (float& v : d) v = std::abs(v);
      std::sort(d.begin(), d.end());
      if (d[1] < 0.5f) continue;
      ++interior;
      worst = std::max(worst, double(ao[i]));
    }
    std::printf("closed box, %s: largest AO %.5f over %zu of %zu pixels 0.5 m from other faces\n", method, worst,
                interior, inside);
    EXPECT_EQ(inside, size_t(48 * 32));
    EXPECT_GT(interior, 700u);
    EXPECT_LE(worst, std::string(method) == "ldm" ? 0.048 : 1e-4);
  }
}

// The GPU's ray-traced AO against the CPU's double-precision rays along the same directions from
// the GPU's own positions and normals (the shadow pass's analysis output, which the AO pass
// computes with the same functions: surface.glsl.inc, improved normals on the hardware path).
// Per pixel the two sums agree to the float sum's rounding (64 terms: 64u) unless a ray passes
// within rounding of an edge or grazes a surface; such a direction moves AO by at most 2·|n·v|/N.
// The same with backend=compute (our BVH, compute_occluded.glsl.inc): held to the same bounds, and
// to the ray-query AO pixel for pixel where neither differs from the CPU rays, unless the pixel has
// a direction whose weight 2·|n·v|/N fits in the tolerance and whose CPU ray changes its answer
// within the float origin's rounding, so that one backend may count it and the other not while
// both match the CPU (seen once: |n·v| ≈ 1e-5, a difference of 3e-7, after the slab test's fma form
// of compute_occluded.glsl.inc changed which of two tracers counted it).
TEST_F(AoGpuTest, RayTracedAoEqualsTheCpuDoubleRaysFromTheSamePositions) {
  const Scene scene = makeAtrium(AtriumParams{});
  std::vector<float> byAuto;
  for (const char* backend : {"auto", "compute"}) {
    SCOPED_TRACE(std::string("backend=") + backend);
    RenderSettings rs = aoSettings(64, 36, {{"method", "raytraced"}});
    rs.normals = NormalCulling::Improved;
    rs.backend = hb::testing::backendNamed(backend);
    Renderer r(*ctx, scene, rs);
    r.renderFrame(true);
    EXPECT_EQ(r.part<AoPart>("ambient_occlusion")->computeBvh() != nullptr, std::string(backend) == "compute");
    const std::vector<float> ao = aoPassOf(r)->readAo();
    const ShadowReadback sh = shadowsOf(r)->readShadows();
    const Bvh bvh = buildBvh(scene);
    const std::vector<glm::dvec3> dirs = ldmDirections(64);
    size_t compared = 0, equal = 0, sameAsAuto = 0, bothExact = 0, lightOnly = 0;
    double sumDiff = 0;
    for (size_t i = 0; i < ao.size(); ++i) {
      if (ao[i] < 0.0f) continue;
      const glm::dvec3 p(sh.positions[4 * i], sh.positions[4 * i + 1], sh.positions[4 * i + 2]);
      const glm::dvec3 n(sh.normals[4 * i], sh.normals[4 * i + 1], sh.normals[4 * i + 2]);
      if (!(glm::dot(n, n) > 0.5)) continue;
      const double tMin = std::max(double(gpu::kShadowTMin), 0.0);
      const double cpu = aoRayTraced(bvh, p, glm::normalize(n), dirs, std::numeric_limits<double>::infinity(), tMin);
      ++compared;
      const double d = std::abs(cpu - double(ao[i]));
      equal += d <= 64.0 * 5.96e-8;
      sumDiff += d;
      if (!byAuto.empty() && d <= 64.0 * 5.96e-8 && std::abs(cpu - double(byAuto[i])) <= 64.0 * 5.96e-8) {
        ++bothExact;
        // Within the tolerance of the CPU both, yet unequal: one tracer counted a direction the
        // other did not. That is allowed only for a direction that is (a) light enough to hide in
        // the tolerance, 0 < 2|n·v|/N <= the difference + 64u, and (b) within rounding of a
        // surface: the CPU's own double ray along it changes its answer when the origin moves by 4
        // float ulps of the position along the normal, either way (the GPU's float origin and
        // offset are that uncertain). A difference with no such direction fails.
        bool ambiguous = false;
        if (ao[i] != byAuto[i]) {
          const glm::dvec3 nn = glm::normalize(n);
          const double diff = std::abs(double(ao[i]) - double(byAuto[i]));
          const double big = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z), 1.0});
          const double h = 4.0 * std::ldexp(1.0, std::ilogb(big) - 23);  // 4 float ulps at |p|
          const double from = std::nextafter(tMin, std::numeric_limits<double>::infinity()),
                       inf = std::numeric_limits<double>::infinity();
          for (const glm::dvec3& v : dirs) {
            const double c = glm::dot(nn, v), w = 2.0 * std::abs(c) / double(dirs.size());
            if (c == 0.0 || w > diff + 64.0 * 5.96e-8) continue;
            const glm::dvec3 dir = c > 0.0 ? v : -v;
            const bool at = bvh.occluded(p, dir, from, inf);
            if (at != bvh.occluded(p + h * nn, dir, from, inf) || at != bvh.occluded(p - h * nn, dir, from, inf)) {
              ambiguous = true;
              break;
            }
          }
        }
        sameAsAuto += ao[i] == byAuto[i] || ambiguous;
        lightOnly += ao[i] != byAuto[i] && ambiguous;
      }
    }
    std::printf(
        "atrium 64x36, %s raytraced AO vs CPU double rays: %zu of %zu pixels equal, mean |difference| %.2g; %zu "
        "pixel(s) matching the CPU differ from the first backend's by a direction light enough to hide in the "
        "tolerance and within rounding of a surface\n",
        backend, equal, compared, compared ? sumDiff / double(compared) : 0.0, lightOnly);
    EXPECT_GT(compared, 1500u);
    EXPECT_GE(double(equal), 0.98 * double(compared));
    EXPECT_LE(sumDiff / double(compared), 1e-3);
    // Both within the float sum's rounding of the CPU: the same rays hit, the same float sum, but
    // for directions too light to show and within rounding of a surface (above).
    if (!byAuto.empty()) {
      EXPECT_EQ(sameAsAuto, bothExact)
          << "pixels where both match the CPU rays but differ by more than a light, ambiguous direction";
    }
    byAuto = ao;
  }
}

// The issue's bounds for the LDM approximation (against raytraced, unlimited d_max): at N = 64 and
// 128² maps MAE <= 0.015, RMSE <= 0.03, |bias| <= 0.01 (a CPU study on the atrium measured MAE
// 0.0104, bias +0.006); at N = 128 and 256² MAE <= 0.007 (the study: 0.0044). Like the study, on
// the exact surface: 3DR's hit positions and the triangles' own normals. (With positions and
// normals reconstructed from the hardware prepass's depth the first case measures MAE 0.0137,
// RMSE 0.0314, bias +0.0104: a reconstructed normal beside an edge tilts the slope-scaled bias.)
//
// The issue gives no RMSE or bias target at N = 128, 256²; they follow from the first case's by how
// the LDM's error scales with the map resolution R and the direction count N. Both methods trace
// the same N directions from the same surface, so per pixel e = AO_ldm − AO_rt = Σ_i w_i·δ_i, with
// weights w_i = (2/N)·|n·v_i| (Σ w_i ≈ 1, the quadrature) and δ_i ∈ {−1, 0, +1} where the LDM's
// answer for direction i differs from the ray's. It differs only within a map pixel of the ray:
// an occluder nearer than the bias is missed (ldm_trace.glsl.inc: bias = (√2/2)·(2r/R)·tan θ +
// 16u·2r, the second term 2^-20 of the first at R = 256) or an occluder's edge passes within half
// a map-pixel diagonal (√2/2)·(2r/R) of the ray. Both widths are ∝ 1/R (N does not enter), and
// they shrink the error in one of two ways:
//  - spread: at every pixel the share of directions that differ is ∝ 1/R (an angular band beside
//    each occluder edge), so e itself is ∝ 1/R at every pixel, and so are MAE, RMSE and bias; the
//    sampling of that band by N directions adds a variance ∝ p/N, which doubling N and R quarters;
//  - concentrated: pixels within a bias of a contact (a corner) differ in many directions, by O(1);
//    their share of the image is ∝ 1/R, so MAE and bias are ∝ 1/R but RMSE = √(share·O(1)) ∝ 1/√R.
// The bias (a mean, linear in the shares) halves either way; RMSE falls at least by √(1/2). So at
// N = 128, 256²: |bias| <= 0.01·(128/256) = 0.005 and RMSE <= 0.03·√(128/256) = 0.0212 (MAE, ∝ 1/R,
// would be 0.0075: the issue's 0.007 is a little tighter). lavapipe measures RMSE 0.0213 -> 0.0116
// (x0.54, near the spread limit) and bias +0.0063 -> +0.0020 from the first case to the second.
TEST_F(AoGpuTest, OnTheAtriumTheLdmApproximationStaysWithinTheIssuesBounds) {
  const Scene scene = makeAtrium(AtriumParams{});
  struct Case {
    uint32_t n, res;
    double mae, rmse, bias;
  };
  // The second case's RMSE and bias bounds: the first case's scaled by the map resolutions (above).
  const double scale = 128.0 / 256.0;
  for (const Case c :
       {Case{64, 128, 0.015, 0.03, 0.01}, Case{128, 256, 0.007, 0.03 * std::sqrt(scale), 0.01 * scale}}) {
    RenderSettings rs = aoSettings(128, 72, {{"directions", c.n}, {"ldm_resolution", c.res}});
    rs.primary = hb::testing::primaryNamed("3dr");
    rs.worldPos = WorldPosMethod::Hit;
    rs.normals = NormalCulling::Geometric;
    Renderer r(*ctx, scene, rs);
    r.renderFrame(true);
    const std::vector<float> ldm = aoPassOf(r)->readAo();
    const std::vector<float> rt = aoPassOf(r)->computeWith(AoMethod::RayTraced);
    const AoErrors e = aoErrors(ldm, rt, 128, 72);
    std::printf(
        "atrium 128x72, ldm N=%u %ux%u vs raytraced: MAE %.4f, RMSE %.4f, bias %+.4f, p95 %.4f, FLIP %.4f over %llu "
        "pixels\n",
        c.n, c.res, c.res, e.mae, e.rmse, e.bias, e.p95, e.flip, (unsigned long long)e.pixels);
    EXPECT_GT(e.pixels, 8000u);
    EXPECT_LE(e.mae, c.mae);
    EXPECT_LE(e.rmse, c.rmse);
    EXPECT_LE(std::abs(e.bias), c.bias);
  }
}

// The lists' depths do not depend on the order fragments arrive in (max64 and cas keep each list
// sorted whatever the order, sbuffer sorts each range; equal depths are equal values), so AO is bit
// for bit the same when the scene is drawn in another order, for both builds and every list.
TEST_F(AoGpuTest, LdmAoIsBitForBitTheSameWhenTheDrawOrderIsShuffled) {
  for (const char* build : {"hardware", "3dr"})
    for (const char* list : {"max64", "cas", "sbuffer"}) {
      SCOPED_TRACE(std::string(build) + ", " + list);
      Scene scene = makeAtrium(AtriumParams{});
      const RenderSettings rs = aoSettings(
          64, 36, {{"directions", 16}, {"ldm_resolution", 64}, {"ldm_build", build}, {"ldm_list", list}}, false);
      const std::vector<float> a = aoOf(*ctx, scene, rs);
      std::reverse(scene.instances.begin(), scene.instances.end());
      for (Mesh& m : scene.meshes) std::reverse(m.primitives.begin(), m.primitives.end());
      const std::vector<float> b = aoOf(*ctx, scene, rs);
      EXPECT_EQ(a, b);
    }
}

// Screen-space HBAO and GTAO need neither maps nor a ray tracer: with shadows off the frame builds no
// acceleration structures and no LDM. (Its error against the ray tracer is what the analysis and
// the AO table report: the paper's point is that it fails for a large kernel.)
TEST_F(AoGpuTest, HbaoAndGtaoBuildNoMapsAndNoRayTracer) {
  const Scene scene = openSky();
  for (const char* method : {"hbao", "gtao"}) {
    SCOPED_TRACE(method);
    Renderer r(*ctx, scene, aoSettings(32, 32, {{"method", method}}, false));
    EXPECT_EQ(r.accel(), nullptr);
    EXPECT_EQ(aoPassOf(r)->ldm(), nullptr);
    EXPECT_FALSE(r.plan().hasPass("ldm_build"));
    r.renderFrame(true);
    EXPECT_FALSE(aoPassOf(r)->canTrace());
  }
}

// The analysis frame's reference takes 1,024 rays a pixel whatever the run's own samples: a
// reference run at 64 is measured against it (its stratified jitter differs from the 1,024-ray
// one at most pixels of the atrium, so the two images differ), and a run at 1,024 is its own.
TEST_F(AoGpuTest, ACheaperReferenceRunIsMeasuredAgainstTheFullReference) {
  const Scene scene = makeAtrium(AtriumParams{});
  Renderer cheap(*ctx, scene, aoSettings(64, 36, {{"method", "reference"}, {"samples", 64}}));
  cheap.renderFrame(true);
  const std::vector<float> own = aoPassOf(cheap)->readAo(), full = aoPassOf(cheap)->computeWith(AoMethod::Reference);
  ASSERT_EQ(own.size(), full.size());
  size_t differ = 0;
  for (size_t i = 0; i < own.size(); ++i) differ += own[i] != full[i];
  EXPECT_GT(differ, own.size() / 4);
  Renderer exact(*ctx, scene, aoSettings(64, 36, {{"method", "reference"}, {"samples", 1024}}));
  exact.renderFrame(true);
  EXPECT_EQ(aoPassOf(exact)->readAo(), full);
}

// A scene that does not call for AO (or cannot: no ambient term) builds nothing for it.
TEST_F(AoGpuTest, WithoutTheEffectNoLdmIsBuiltAndNothingIsAllocated) {
  Scene scene = openSky();
  RenderSettings rs;
  rs.width = 32;
  rs.height = 32;
  {
    Renderer r(*ctx, scene, rs);
    EXPECT_EQ(aoPassOf(r), nullptr);
    r.renderFrame(false);
    EXPECT_EQ(std::count(r.passesRun().begin(), r.passesRun().end(), "ldm_build"), 0);
  }
  scene.ambient.reset();
  Renderer r(*ctx, scene, aoSettings(32, 32, true));
  EXPECT_EQ(aoPassOf(r), nullptr);
  EXPECT_FALSE(r.plan().runs("ambient_occlusion"));
}

}  // namespace
}  // namespace hb
