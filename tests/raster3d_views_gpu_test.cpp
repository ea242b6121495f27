// Views a hardware rasterizer cannot draw (3DR paper Section 3.5), and the orthographic one
// (Section 3.3), through 3D rasterization on the real device: the fill rule on closed meshes around
// the eye (every ray meets the mesh exactly once, so every pixel with a ray must be covered exactly
// once, counted additively over all triangles at every depth: a crack is a 0, a double cover a 2,
// with no CPU reference needed), binned equal to brute force bit for bit, agreement with ray
// casting along the same rays on the atrium, and the settings such views need.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "analysis/primary_analysis.h"
#include "base/errors.h"
#include "effects/shadows/shadows_part.h"
#include "frame/passes/raster3d.h"
#include "frame/renderer.h"
#include "gpu_fixture.h"
#include "scene/atrium.h"
#include "scene/mesh_builder.h"

namespace hb {
namespace {

struct ViewCase {
  CameraProjection projection;
  uint32_t width, height;
};
// Latlong 2:1 (square pixels on the sphere's equator), the paraboloid's disk in a wide frame (so
// that pixels outside it exist), orthographic 4:3.
const ViewCase kViews[] = {{CameraProjection::Latlong, 96, 48},
                           {CameraProjection::Paraboloid, 80, 64},
                           {CameraProjection::Orthographic, 64, 48}};

// An eye off every axis, looking along an oblique direction with a tilted up vector.
Camera viewCamera(CameraProjection p) {
  Camera cam;
  cam.view = lookAt(glm::vec3(0.37f, -0.21f, 0.13f), glm::vec3(-0.4f, 0.2f, -1.9f), glm::vec3(0.1f, 1.0f, 0.05f));
  cam.projection = p;
  cam.xmag = 0.6f;  // orthographic: the view (1.2 x 0.9) lies inside the cube's cross-section
  cam.ymag = 0.45f;
  cam.znear = 0.01f;
  cam.zfar = 100.0f;
  return cam;
}

// A cube of n x n quads per face, side 2·half, centred at the origin and turned by `pose`, with every
// lattice point computed by one function of its integer coordinates, so that faces that share an
// edge share its vertices bit for bit. Closed, so a ray from inside meets it exactly once.
void addLatticeCube(Scene& s, int n, double half, const glm::dmat4& pose) {
  auto point = [&](int a, int b, int c) {
    const glm::dvec3 q = glm::dvec3(a, b, c) * (2.0 * half / n) - glm::dvec3(half);
    return glm::vec3(pose * glm::dvec4(q, 1.0));
  };
  const uint32_t first = uint32_t(s.indices.size()), base = uint32_t(s.vertices.size());
  auto tri = [&](glm::vec3 p0, glm::vec3 p1, glm::vec3 p2) {
    for (glm::vec3 p : {p0, p1, p2}) {
      s.indices.push_back(uint32_t(s.vertices.size() - base));
      s.vertices.push_back({p, glm::vec3(0, 0, 1), glm::vec2(0)});
    }
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side <= n; side += n)
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          auto at = [&](int u, int v) {
            int c[3];
            c[axis] = side;
            c[(axis + 1) % 3] = u;
            c[(axis + 2) % 3] = v;
            return point(c[0], c[1], c[2]);
          };
          // Alternate diagonals, so that vertices have 4, 6 and 8 triangles around them.
          if ((i + j) % 2 == 0) {
            tri(at(i, j), at(i + 1, j), at(i + 1, j + 1));
            tri(at(i, j), at(i + 1, j + 1), at(i, j + 1));
          } else {
            tri(at(i, j), at(i + 1, j), at(i, j + 1));
            tri(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
          }
        }
  const uint32_t count = uint32_t(s.indices.size()) - first;
  s.meshes.push_back({"cube", {{first, count, base, uint32_t(s.vertices.size()) - base, 0}}});
  s.instances.push_back({uint32_t(s.meshes.size() - 1), glm::mat4(1.0f)});
}

Scene cubeScene(const Camera& cam, int n, const glm::dmat4& pose) {
  Scene s;
  s.name = "lattice cube";
  s.materials.push_back({});
  s.cameras.push_back(cam);
  addLatticeCube(s, n, 1.5, pose);
  return s;
}

RenderSettings viewSettings(const ViewCase& v, const char* primary) {
  RenderSettings rs;
  rs.width = v.width;
  rs.height = v.height;
  rs.primary = hb::testing::primaryNamed(primary);
  rs.shading = ShadingMethod::Visbuffer;
  rs.lightCulling = false;
  rs.worldPos = WorldPosMethod::Hit;
  rs.normals = NormalCulling::Geometric;
  return rs;
}

struct Frame {
  std::vector<uint32_t> count;
  std::vector<uint64_t> vis;
  Raster3dCounters counters;
  gpu::Raster3dConstants rays;
};

Frame render(const VulkanContext& ctx, const Scene& scene, const RenderSettings& rs) {
  Renderer r(ctx, scene, rs);
  r.renderFrame(true);
  return {r.raster3d()->readCoverage(), r.raster3d()->readVisibility(), r.raster3d()->readCounters(),
          raster3dConstants(r.camera(), rs.width, rs.height, 0, 0)};
}

bool hasRay(const gpu::Raster3dConstants& c, uint32_t x, uint32_t y) {  // camera_ray.glsl.inc
  if (c.projection != gpu::kProjectionParaboloid) return true;
  const float u = (float(x) - c.view.x) * c.view.z, v = (c.view.y - float(y)) * c.view.z;
  return u * u + v * v <= 1.0f;
}

class Raster3dViewsTest : public testing::GpuTest {};

TEST_F(Raster3dViewsTest, ClosedLatticeCubesAroundTheEyeAreCoveredExactlyOncePerRay) {
  // 5 orientations x 3 views x (3dr, 3dr-binned). Latlong: the cube's faces wrap the seam and
  // both poles; paraboloid: the rim cuts faces; orthographic: rays start inside the cube.
  for (const ViewCase& v : kViews) {
    uint64_t fallbacks = 0, evaluations = 0, refined = 0, empty = 0;
    for (int k = 0; k < 5; ++k) {
      const glm::dmat4 pose =
          glm::rotate(glm::dmat4(1.0), 0.3 + 0.77 * k, glm::normalize(glm::dvec3(1.0, 2.0 + k, 0.5)));
      const Scene s = cubeScene(viewCamera(v.projection), 6 + k, pose);
      SCOPED_TRACE(std::string(toString(v.projection)) + ", orientation " + std::to_string(k));
      const Frame brute = render(*ctx, s, viewSettings(v, "3dr"));
      const Frame binned = render(*ctx, s, viewSettings(v, "3dr-binned"));
      // Every ray meets the cube once: rays from the eye, and orthographic rays, which are
      // half-lines in front of the view plane (raster3d.glsl.inc drops a line's hit behind it).
      const uint32_t expected = 1u;
      size_t withRay = 0, holes = 0, twice = 0, outside = 0;
      for (uint32_t y = 0; y < v.height; ++y)
        for (uint32_t x = 0; x < v.width; ++x) {
          const uint32_t c = brute.count[size_t(y) * v.width + x];
          if (!hasRay(brute.rays, x, y)) {
            outside += c != 0;
            continue;
          }
          ++withRay;
          holes += c < expected;
          twice += c > expected;
        }
      EXPECT_GT(withRay, size_t(v.width) * v.height / 2);
      EXPECT_EQ(holes, 0u);
      EXPECT_EQ(twice, 0u);
      EXPECT_EQ(outside, 0u);
      EXPECT_EQ(binned.vis, brute.vis);
      EXPECT_EQ(binned.count, brute.count);
      fallbacks += brute.counters.fallbacks;
      evaluations += brute.counters.edgeEvaluations;
      refined += binned.counters.binsRefined;
      empty += binned.counters.binsEmpty;
    }
    std::printf("%s: fp64 fallback on %llu of %llu edge evaluations; binned: %llu of %llu refined bins without a hit\n",
                toString(v.projection), (unsigned long long)fallbacks, (unsigned long long)evaluations,
                (unsigned long long)empty, (unsigned long long)refined);
  }
}

TEST_F(Raster3dViewsTest, TheAtriumThroughEveryViewAgreesWithRayCastingAlongTheSameRays) {
  // The bound: 3DR and the ray cast name the same triangle on >= 99.99 % of the pixels
  // either hits (at 160x90 that allows one pixel); both are held to the double ray cast too.
  const Scene atrium = makeAtrium(AtriumParams{});
  const Bvh bvh = buildBvh(atrium);
  for (CameraProjection p : {CameraProjection::Latlong, CameraProjection::Paraboloid, CameraProjection::Orthographic}) {
    SCOPED_TRACE(toString(p));
    RenderSettings rs = viewSettings({p, 160, 90}, "3dr");
    rs.projection = p;
    const Frame r3 = render(*ctx, atrium, rs);
    rs.primary = hb::testing::primaryNamed("raycast");
    const Frame rc = render(*ctx, atrium, rs);
    rs.primary = hb::testing::primaryNamed("3dr-binned");
    const Frame bin = render(*ctx, atrium, rs);
    EXPECT_EQ(bin.vis, r3.vis);
    // A pixel agrees when both name the same triangle (or both nothing), or both hit within the
    // depth tie of each other (primary_analysis.h kTieDepth·tieScale: touching surfaces, whose
    // order float cannot decide); the ties are counted and printed.
    size_t either = 0, same = 0, ties = 0;
    for (size_t i = 0; i < r3.vis.size(); ++i) {
      if (r3.vis[i] == ~0ull && rc.vis[i] == ~0ull) continue;
      ++either;
      if (r3.vis[i] == ~0ull || rc.vis[i] == ~0ull) continue;
      if (uint32_t(r3.vis[i]) == uint32_t(rc.vis[i])) {
        ++same;
        continue;
      }
      const double ta = std::bit_cast<float>(uint32_t(r3.vis[i] >> 32)),
                   tb = std::bit_cast<float>(uint32_t(rc.vis[i] >> 32));
      const uint32_t x = uint32_t(i % 160), y = uint32_t(i / 160);
      const glm::dvec3 offset = glm::dvec3(r3.rays.origin0) + double(x) * glm::dvec3(r3.rays.originX) +
                                double(y) * glm::dvec3(r3.rays.originY);
      const bool tie = std::abs(ta - tb) <=
                       kTieDepth * tieScale(ta, p == CameraProjection::Orthographic ? glm::length(offset) : 0.0);
      ties += tie;
      same += tie;
    }
    const PrimaryComparison c = comparePrimary(bvh, r3.vis, r3.rays);
    std::printf(
        "atrium %s 160x90: 3dr and raycast agree on %zu of %zu pixels (%zu of them depth ties); vs double ray "
        "cast %llu ids equal of %llu, %llu not ties, depth p99.9 %.3g\n",
        toString(p), same, either, ties, (unsigned long long)c.idsEqual, (unsigned long long)c.bothHit,
        (unsigned long long)c.notTies, c.depthRelP999);
    EXPECT_GT(either, 5000u);
    EXPECT_GE(double(same), 0.9999 * double(either));
  }
}

// The hardware path draws orthographic views through camera.h's reverse-Z orthographic matrix
// (depth affine in view depth t: D − C·t), and 3DR writes the same mapping from its hit's t, so the
// frame reads one depth convention whichever method drew it. Held here: the hardware prepass's depth
// against 3DR's, and positions turned back from the hardware depth (Alg. 4.1 and the inverse
// matrix, both taking the orthographic form) against 3DR's exact hit positions.
//
// Bounds (u = 2^-24): the depth image stores D − C·t, C = 1/(zf − zn); the rasterizer interpolates
// it with a few u of absolute error (depth ≤ 1), 3DR's t carries a few u·t and its D − C·t two
// roundings: |Δdepth| ≤ 8u, so |Δt| ≤ 8u·(zf − zn) + 4u·t ≤ 12u·(zf − zn). A position adds the
// rounding of ndc·xmag and of viewInv·v (≤ 8u of |eye| + |v|). Both allow 16u of
// zf − zn + |eye| + |xmag, ymag|. The two fill rules may give an edge pixel to different triangles,
// and a surface behind may be within rounding of the front: 99 % of pixels must hold it.
TEST_F(Raster3dViewsTest, TheHardwarePathDrawsOrthographicViewsWithTheDepthAndPositions3drGives) {
  const Scene atrium = makeAtrium(AtriumParams{});
  struct Out {
    std::vector<float> depth, positions;
    Camera cam;
  };
  auto run = [&](const char* primary, WorldPosMethod worldPos) {
    RenderSettings rs;
    rs.width = 160;
    rs.height = 90;
    rs.primary = hb::testing::primaryNamed(primary);
    rs.projection = CameraProjection::Orthographic;
    rs.lightCulling = false;
    rs.worldPos = worldPos;
    rs.shading = (std::string(primary) != "hardware") ? ShadingMethod::Visbuffer : ShadingMethod::Forward;
    Renderer r(*ctx, atrium, rs);
    r.renderFrame(true);
    return Out{r.readDepth(), shadowsOf(r)->readShadows().positions, r.camera()};
  };
  const Out hit = run("3dr", WorldPosMethod::Hit);
  const double u = 5.9604644775390625e-8, zn = hit.cam.znear, zf = hit.cam.zfar;
  const glm::dvec3 eye = glm::dvec3(glm::inverse(glm::dmat4(hit.cam.view))[3]);
  const double bound = 16.0 * u * (zf - zn + glm::length(eye) + std::max(hit.cam.xmag, hit.cam.ymag));
  for (WorldPosMethod worldPos : {WorldPosMethod::Alg41, WorldPosMethod::Matrix}) {
    SCOPED_TRACE(worldPos == WorldPosMethod::Alg41 ? "alg41" : "matrix");
    const Out hw = run("hardware", worldPos);
    size_t both = 0, depthClose = 0, positionClose = 0, skyMismatch = 0;
    double worstClose = 0;
    for (size_t i = 0; i < hw.depth.size(); ++i) {
      if ((hw.depth[i] == 0.0f) != (hit.depth[i] == 0.0f)) ++skyMismatch;
      if (hw.depth[i] == 0.0f || hit.depth[i] == 0.0f) continue;
      ++both;
      const double dt = std::abs(double(hw.depth[i]) - hit.depth[i]) * (zf - zn);
      depthClose += dt <= bound;
      const glm::dvec3 a(hw.positions[4 * i], hw.positions[4 * i + 1], hw.positions[4 * i + 2]);
      const glm::dvec3 b(hit.positions[4 * i], hit.positions[4 * i + 1], hit.positions[4 * i + 2]);
      const double dp = glm::length(a - b);
      positionClose += dp <= bound;
      if (dp <= bound) worstClose = std::max(worstClose, dp / bound);
    }
    std::printf(
        "atrium orthographic 160x90, hardware vs 3dr: %zu pixels both hit, depth within the bound on %zu, "
        "positions on %zu (largest of those %.2f of the bound %.3g m), %zu sky mismatches\n",
        both, depthClose, positionClose, worstClose, bound, skyMismatch);
    EXPECT_GT(both, 10000u);
    EXPECT_GE(double(depthClose), 0.99 * double(both));
    EXPECT_GE(double(positionClose), 0.99 * double(both));
    EXPECT_LE(skyMismatch, hw.depth.size() / 1000);
  }
}

TEST_F(Raster3dViewsTest, ViewsAMethodCannotDrawAreRefusedWithWhatToSet) {
  const Scene atrium = makeAtrium(AtriumParams{});
  auto message = [&](RenderSettings rs) {
    try {
      Renderer r(*ctx, atrium, rs);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  RenderSettings rs = viewSettings({CameraProjection::Latlong, 64, 32}, "hardware");
  rs.projection = CameraProjection::Latlong;
  EXPECT_NE(message(rs).find("needs primary=3dr, 3dr-binned or raycast"), std::string::npos) << message(rs);
  rs.primary = hb::testing::primaryNamed("3dr");
  rs.shading = ShadingMethod::Forward;
  EXPECT_NE(message(rs).find("needs shading=visbuffer"), std::string::npos) << message(rs);
  rs.shading = ShadingMethod::Visbuffer;
  rs.lightCulling = true;
  EXPECT_NE(message(rs).find("needs light_culling=false"), std::string::npos) << message(rs);
  rs.lightCulling = false;
  rs.worldPos = WorldPosMethod::Alg41;
  EXPECT_NE(message(rs).find("needs world_pos=hit"), std::string::npos) << message(rs);
  rs.worldPos = WorldPosMethod::Hit;
  EXPECT_EQ(message(rs), "accepted");
  // Orthographic: the hardware path draws it, with the forward pass and depth-reconstructed
  // positions; 2dr does not; the forward pass does not on top of a compute method.
  rs = viewSettings({CameraProjection::Orthographic, 64, 48}, "hardware");
  rs.projection = CameraProjection::Orthographic;
  rs.shading = ShadingMethod::Forward;
  rs.worldPos = WorldPosMethod::Alg41;
  rs.normals = NormalCulling::Improved;
  EXPECT_EQ(message(rs), "accepted");
  rs.primary = hb::testing::primaryNamed("2dr");
  EXPECT_NE(message(rs).find("needs primary=3dr, 3dr-binned or raycast"), std::string::npos) << message(rs);
  rs.primary = hb::testing::primaryNamed("3dr");
  EXPECT_NE(message(rs).find("needs shading=visbuffer with primary=3dr"), std::string::npos) << message(rs);
}

}  // namespace
}  // namespace hb
