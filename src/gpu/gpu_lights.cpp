#include "gpu/gpu_lights.h"

#include <cmath>

#include "reference/cull_ref.h"

namespace hb {

std::vector<gpu::GpuLight> packLights(const std::vector<Light>& lights) {
  std::vector<gpu::GpuLight> out;
  out.reserve(lights.size());
  for (const Light& l : lights) {
    gpu::GpuLight g{};
    g.positionRange = glm::vec4(l.position, l.range);
    g.directionCosOuter = glm::vec4(glm::normalize(l.direction), std::cos(l.outerConeAngle));
    g.colorIntensity = glm::vec4(l.color, l.intensity);
    g.type = uint32_t(l.type);
    g.cosInner = std::cos(l.innerConeAngle);
    g.castShadows = l.castShadows ? 1u : 0u;
    g.tanOuter = float(spotConeTan(l.outerConeAngle));
    out.push_back(g);
  }
  return out;
}

gpu::FrameConstants makeFrameConstants(const glm::mat4& view, const glm::mat4& proj, uint32_t width, uint32_t height,
                                       uint32_t tileSize, uint32_t lightCount, float tMinPerMetre) {
  gpu::FrameConstants f{};
  f.view = view;
  // Inverses in double, then rounded: a float inverse misplaces the camera by ~1 mm at 10 km from
  // the origin (shadows_gpu_test far-origin), which no reconstruction could undo.
  f.viewInv = glm::mat4(glm::inverse(glm::dmat4(view)));
  f.proj = proj;
  f.viewProj = proj * view;
  f.viewProjInv = glm::mat4(glm::inverse(glm::dmat4(proj) * glm::dmat4(view)));
  f.cameraPos = glm::vec4(glm::vec3(f.viewInv[3]), tMinPerMetre);
  f.extent = glm::vec4(float(width), float(height), 1.0f / float(width), 1.0f / float(height));
  f.tileCountX = (width + tileSize - 1) / tileSize;
  f.tileCountY = (height + tileSize - 1) / tileSize;
  f.tileSize = tileSize;
  f.lightCount = lightCount;
  return f;
}

}  // namespace hb
