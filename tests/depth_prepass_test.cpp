// The depth prepass on the real device against depths computed on the CPU in double precision.
#include <cmath>

#include <gtest/gtest.h>

#include "frame/renderer.h"
#include "gpu_fixture.h"
#include "scene/camera.h"

namespace hb {
namespace {

// A quad (two triangles) in the plane through `center` with normal `n`, large enough to fill the view.
Scene tiltedPlaneScene(glm::vec3 center, glm::vec3 n) {
  Scene s;
  s.name = "tilted-plane";
  n = glm::normalize(n);
  glm::vec3 u = glm::normalize(glm::cross(n, glm::vec3(0, 1, 0.3f)));
  glm::vec3 v = glm::cross(n, u);
  const float h = 50.0f;
  glm::vec3 c[4] = {center - h * u - h * v, center + h * u - h * v, center + h * u + h * v, center - h * u + h * v};
  for (auto& p : c) s.vertices.push_back({p, n, {0, 0}});
  s.indices = {0, 1, 2, 0, 2, 3};
  s.meshes.push_back({"plane", {{0, 6, 0, 4, 0}}});
  s.instances.push_back({0, glm::mat4(1.0f)});
  s.materials.push_back({});
  Camera cam;
  cam.view = glm::mat4(1.0f);  // eye at origin looking down -z
  cam.yfov = 1.0f;
  cam.znear = 0.1f;
  cam.zfar = 100.0f;
  s.cameras.push_back(cam);
  return s;
}

// Expected reverse-Z depth at the centre of pixel (px, py): intersect the pixel's view ray with
// the plane in double precision, then apply eq. 2.1's C and D: depth = -C + D / (-z).
double expectedDepth(uint32_t px, uint32_t py, uint32_t w, uint32_t h, const Camera& cam, glm::dvec3 center,
                     glm::dvec3 n) {
  glm::dmat4 p = reverseZProjectionD(double(w) / h, cam.yfov, cam.znear, cam.zfar);
  double ndcX = 2.0 * (px + 0.5) / w - 1.0, ndcY = 2.0 * (py + 0.5) / h - 1.0;
  glm::dvec3 dir(ndcX / p[0][0], ndcY / p[1][1], -1.0);  // the view ray through the pixel (z = -1)
  double t = glm::dot(n, center) / glm::dot(n, dir);
  double z = -t;  // dir.z = -1
  return -p[2][2] + p[3][2] / (-z);
}

class DepthPrepassTest : public testing::GpuTest {};

TEST_F(DepthPrepassTest, MatchesCpuDepthsOfATiltedPlane) {
  const glm::vec3 center(0.3f, -0.2f, -6.0f), normal(0.4f, 0.25f, 1.0f);
  Scene scene = tiltedPlaneScene(center, normal);
  RenderSettings settings;
  settings.width = 97;  // odd sizes on purpose
  settings.height = 61;
  Renderer renderer(*ctx, scene, settings);
  renderer.renderFrame();
  std::vector<float> depth = renderer.readDepth();
  ASSERT_EQ(depth.size(), size_t(97 * 61));
  // Tolerance: the vertex shader forms clip z and w as 4-term float dot products (relative error
  // <= 4 eps each, eps = 2^-24), the divide adds 1 eps, and the rasteriser interpolates z/w with
  // barycentrics computed in float (<= ~3 eps of the largest |z_ndc| over the triangle). depth is
  // <= 1 here, so |error| <= ~12 eps ~= 7.2e-7; allow 16 eps = 9.5e-7.
  const double tol = 16.0 * std::ldexp(1.0, -24);
  for (uint32_t py : {0u, 7u, 30u, 60u})
    for (uint32_t px : {0u, 13u, 48u, 96u}) {
      double want =
          expectedDepth(px, py, 97, 61, scene.cameras[0], glm::dvec3(center), glm::normalize(glm::dvec3(normal)));
      EXPECT_NEAR(depth[py * 97 + px], want, tol) << "pixel " << px << "," << py;
    }
}

TEST_F(DepthPrepassTest, ClearsToZeroWhereThereIsNoGeometry) {
  // A plane facing away behind the camera: nothing visible, every pixel keeps the clear value 0.
  Scene scene = tiltedPlaneScene({0, 0, 10}, {0, 0, 1});
  RenderSettings settings;
  settings.width = 32;
  settings.height = 16;
  Renderer renderer(*ctx, scene, settings);
  FrameTiming t = renderer.renderFrame();
  for (float d : renderer.readDepth()) ASSERT_EQ(d, 0.0f);
  // A scene without lights runs the prepass and the shading pass only (nothing to cull or trace).
  ASSERT_EQ(t.passMs.size(), 2u);
  EXPECT_EQ(t.passMs[0].first, "depth_prepass");
  EXPECT_EQ(t.passMs[1].first, "shading");
  EXPECT_GE(t.passMs[0].second, 0.0);
  // light_culling and shadows, ambient occlusion's two, the indirect light's four and the
  // environment light's two (off unless called for), each with its reason
  EXPECT_EQ(renderer.passesSkipped().size(), 10u);
}

}  // namespace
}  // namespace hb
