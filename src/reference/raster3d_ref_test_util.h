// Shared by the CPU 3D rasterization tests (raster3d_ref_test.cpp, raster3d_ref_accuracy_test.cpp).
#pragma once
#include <cstdint>
#include <random>

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
inline Raster3dView randomView(std::mt19937& rng, uint32_t w, uint32_t h) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const glm::dvec3 eye(3 * u(rng), 3 * u(rng), 3 * u(rng));
  const glm::dvec3 dir = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)) + glm::dvec3(0.0, 0.0, -1.5));
  Camera cam;
  cam.view = glm::mat4(glm::lookAtRH(eye, eye + dir, glm::dvec3(0.3 * u(rng), 1.0, 0.3 * u(rng))));
  cam.yfov = float(0.7 + 0.4 * (u(rng) + 1.0));
  cam.znear = 0.05f;
  cam.zfar = 200.0f;
  return pinholeView(cam, w, h);
}

}  // namespace hb::raster3d_test
