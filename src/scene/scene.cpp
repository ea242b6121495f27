#include "scene/scene.h"

#include <cmath>
#include <limits>

namespace hb {

const char* toString(CameraProjection p) {
  switch (p) {
    case CameraProjection::Perspective: return "perspective";
    case CameraProjection::Orthographic: return "orthographic";
    case CameraProjection::Paraboloid: return "paraboloid";
    case CameraProjection::Latlong: return "latlong";
  }
  return "?";
}

uint64_t Scene::triangleCount() const {
  uint64_t n = 0;
  for (const Instance& inst : instances)
    for (const Primitive& p : meshes[inst.mesh].primitives) n += p.indexCount / 3;
  return n;
}

void Scene::bounds(glm::vec3& lo, glm::vec3& hi) const {
  lo = glm::vec3(std::numeric_limits<float>::max());
  hi = glm::vec3(-std::numeric_limits<float>::max());
  for (const Instance& inst : instances)
    for (const Primitive& p : meshes[inst.mesh].primitives)
      for (uint32_t v = 0; v < p.vertexCount; ++v) {
        glm::vec3 w = glm::vec3(inst.transform * glm::vec4(vertices[p.vertexOffset + v].position, 1.0f));
        lo = glm::min(lo, w);
        hi = glm::max(hi, w);
      }
}

std::vector<glm::vec3> Scene::worldTriangles() const {
  std::vector<glm::vec3> out;
  out.reserve(size_t(triangleCount()) * 3);
  for (const Instance& inst : instances) {
    const glm::dmat4 m(inst.transform);
    for (const Primitive& p : meshes[inst.mesh].primitives)
      for (uint32_t i = 0; i + 2 < p.indexCount; i += 3)
        for (uint32_t k = 0; k < 3; ++k) {
          const glm::vec3& v = vertices[p.vertexOffset + indices[p.firstIndex + i + k]].position;
          out.push_back(glm::vec3(m * glm::dvec4(glm::dvec3(v), 1.0)));  // one rounding per coordinate
        }
  }
  return out;
}

double rangeFromIntensity(double intensity) { return 50.0 * std::sqrt(0.02 * intensity); }

}  // namespace hb
