// Shared by the CPU 3D rasterization tests (raster3d_ref_test.cpp, raster3d_ref_accuracy_test.cpp)
// and the GPU test of the fast paths' margins (tests/raster3d_margin_gpu_test.cpp).
#pragma once
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "reference/raster3d_ref.h"
#include "scene/scene.h"

namespace hb::raster3d_test {

// The ray through the centre of pixel (x, y), in double from the view's float values.
inline glm::dvec3 rayAt(const Raster3dView& v, double x, double y) {
  return glm::dvec3(v.d0) + x * glm::dvec3(v.dx) + y * glm::dvec3(v.dy);
}

// A camera at a random place, off every axis, so that no product in the edge functions is exact
// by accident (an axis-aligned camera at the origin makes most of them exact).
inline Camera randomCamera(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const glm::dvec3 eye(3 * u(rng), 3 * u(rng), 3 * u(rng));
  const glm::dvec3 dir = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)) + glm::dvec3(0.0, 0.0, -1.5));
  Camera cam;
  cam.view = glm::mat4(glm::lookAtRH(eye, eye + dir, glm::dvec3(0.3 * u(rng), 1.0, 0.3 * u(rng))));
  cam.yfov = float(0.7 + 0.4 * (u(rng) + 1.0));
  cam.znear = 0.05f;
  cam.zfar = 200.0f;
  return cam;
}
inline Raster3dView randomView(std::mt19937& rng, uint32_t w, uint32_t h) {
  return pinholeView(randomCamera(rng), w, h);
}

struct Mesh {
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;
};

// A planar mesh given in pixel coordinates (px, one per vertex), with its outline (a closed loop of
// vertex indices); lifted onto a plane so that every vertex lies on the ray through its pixel
// position (exactly in double, then rounded to float once, as a scene stores it).
struct PixelMesh {
  std::vector<glm::dvec2> px;
  std::vector<uint32_t> indices, outline;
};

// Lifts onto the plane through the point at view depth `depth` on the image centre's ray, with
// its normal tilted from that ray by up to `tilt` radians about a random axis (perspective). A tilt
// that would put a vertex behind the eye or let a ray graze the plane (cos < 0.2) is drawn again.
inline Mesh liftOntoPlane(const Raster3dView& v, const PixelMesh& pm, double depth, double tilt, std::mt19937& rng) {
  const glm::dvec3 c = depth * rayAt(v, v.width / 2.0 - 0.5, v.height / 2.0 - 0.5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (;;) {
    const glm::dvec3 axis = glm::normalize(glm::cross(c, glm::dvec3(u(rng), u(rng), u(rng))));
    const glm::dvec3 n = glm::dvec3(glm::rotate(glm::dmat4(1.0), tilt, axis) * glm::dvec4(glm::normalize(c), 0.0));
    Mesh m;
    bool ok = true;
    for (const glm::dvec2& p : pm.px) {
      const glm::dvec3 d = rayAt(v, p.x, p.y);
      ok = ok && glm::dot(n, d) / glm::length(d) > 0.2;
      m.positions.push_back(glm::vec3(glm::dvec3(v.eye) + (glm::dot(n, c) / glm::dot(n, d)) * d));
    }
    m.indices = pm.indices;
    if (ok) return m;
    tilt *= 0.8;
  }
}

// n × n quads, vertex (i, j) at centre + R(angle)·(i − n/2, j − n/2)·step, rounded to the nearest
// pixel centre if `snap`. Diagonals alternate so that vertices of valence 4 and 8 occur (as in CTS).
inline PixelMesh quadGrid(int n, double step, double angle, glm::dvec2 centre, bool snap) {
  PixelMesh g;
  const double c = std::cos(angle), s = std::sin(angle);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double a = (i - n / 2.0) * step, b = (j - n / 2.0) * step;
      glm::dvec2 p = centre + glm::dvec2(c * a - s * b, s * a + c * b);
      g.px.push_back(snap ? glm::round(p) : p);
    }
  auto id = [n](int i, int j) { return uint32_t(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t a = id(i, j), b = id(i + 1, j), cc = id(i + 1, j + 1), d = id(i, j + 1);
      if ((i + j) % 2 == 0)
        g.indices.insert(g.indices.end(), {a, b, cc, a, cc, d});
      else
        g.indices.insert(g.indices.end(), {a, b, d, b, cc, d});
    }
  for (int i = 0; i < n; ++i) g.outline.push_back(id(i, 0));
  for (int j = 0; j < n; ++j) g.outline.push_back(id(n, j));
  for (int i = n; i > 0; --i) g.outline.push_back(id(i, n));
  for (int j = n; j > 0; --j) g.outline.push_back(id(0, j));
  return g;
}

}  // namespace hb::raster3d_test
