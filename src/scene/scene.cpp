#include "scene/scene.h"

#include <cmath>
#include <limits>

namespace hb {

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

double rangeFromIntensity(double intensity) { return 50.0 * std::sqrt(0.02 * intensity); }

}  // namespace hb
