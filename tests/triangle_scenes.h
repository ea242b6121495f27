// Scenes of bare triangles built in GPU tests: one camera, one material, and meshes of triangles
// given as corners (3 per triangle, no vertex shared between triangles unless the corners repeat
// bit for bit), each mesh with an identity instance.
#pragma once
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <glm/glm.hpp>

#include "scene/camera.h"
#include "scene/scene.h"

namespace hb::testing {

// The eye at the origin looking down −z; yfov 1 rad, near 0.1 m, far 100 m.
inline Camera originCamera() {
  Camera cam;
  cam.view = glm::mat4(1.0f);
  cam.yfov = 1.0f;
  cam.znear = 0.1f;
  cam.zfar = 100.0f;
  return cam;
}

// A camera away from the origin and off every axis, so that no product in the edge functions is
// exact by accident (an axis-aligned camera at the origin makes most of them exact zeros).
inline Camera obliqueCamera() {
  Camera cam = originCamera();
  cam.view = lookAt(glm::vec3(1.37f, 0.71f, 2.13f), glm::vec3(-0.4f, 0.2f, -1.9f), glm::vec3(0.1f, 1.0f, 0.05f));
  return cam;
}

// A scene with `cam` and `material`, and no geometry yet.
inline Scene emptyScene(const char* name, const Camera& cam = originCamera(), const Material& material = {}) {
  Scene s;
  s.name = name;
  s.materials.push_back(material);
  s.cameras.push_back(cam);
  return s;
}

// Appends one mesh of the triangles `corners` (3 per triangle; float or double, stored as float),
// normals +z, material 0.
template <typename Corner>
void addTriangles(Scene& s, const std::vector<Corner>& corners) {
  const uint32_t first = uint32_t(s.indices.size()), base = uint32_t(s.vertices.size());
  for (size_t i = 0; i < corners.size(); ++i) {
    s.vertices.push_back({glm::vec3(corners[i]), glm::vec3(0, 0, 1), glm::vec2(0)});
    s.indices.push_back(uint32_t(i));
  }
  s.meshes.push_back({"mesh", {{first, uint32_t(corners.size()), base, uint32_t(corners.size()), 0}}});
  s.instances.push_back({uint32_t(s.meshes.size() - 1), glm::mat4(1.0f)});
}

// `n` overlapping random triangles in front of `cam` (fixed `seed`), of many sizes (every tenth
// large): depth complexity, and ties only where two triangles really meet.
inline std::vector<glm::vec3> randomSoupCorners(const Camera& cam, uint32_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const glm::mat4 inv = glm::inverse(cam.view);
  std::vector<glm::vec3> tris;
  for (uint32_t i = 0; i < n; ++i) {
    const glm::vec3 c(2.5f * u(rng), 1.5f * u(rng), -3.0f + 2.5f * u(rng));  // view space
    const float size = i % 10 == 0 ? 1.5f : 0.15f;
    for (int k = 0; k < 3; ++k)
      tris.push_back(glm::vec3(inv * glm::vec4(c + size * glm::vec3(u(rng), u(rng), u(rng)), 1.0f)));
  }
  return tris;
}

// A heightfield of n x n quads with shared vertices (two triangles each), in front of
// obliqueCamera: every shared edge and vertex must be covered exactly once.
inline std::vector<glm::vec3> heightfieldCorners(int n) {
  auto v = [&](int i, int j) {
    const float x = -1.2f + 2.4f * float(i) / float(n), z = -3.2f + 2.4f * float(j) / float(n);
    return glm::vec3(x, 0.15f * std::sin(3.0f * x) * std::cos(2.0f * z) - 0.3f, z);
  };
  std::vector<glm::vec3> tris;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const glm::vec3 a = v(i, j), b = v(i + 1, j), c = v(i + 1, j + 1), d = v(i, j + 1);
      tris.insert(tris.end(), {a, b, c, a, c, d});
    }
  return tris;
}

}  // namespace hb::testing
