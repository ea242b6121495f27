#include "analysis/ray_oracle.h"

#include <algorithm>
#include <cmath>

#include "base/parallel.h"

namespace hb {

OracleRays oracleRays(const Scene& scene, const ReferenceSurface& surface) {
  OracleRays o;
  o.perPixel.assign(surface.state.size(), 0);
  // The light terms once, then every pixel on every core (each writes its own count).
  std::vector<glm::dvec3> axes, positions;
  std::vector<double> cosOuter;
  for (const Light& light : scene.lights) {
    axes.push_back(glm::normalize(glm::dvec3(light.direction)));
    positions.push_back(glm::dvec3(light.position));
    cosOuter.push_back(std::cos(double(light.outerConeAngle)));
  }
  const size_t width = std::max<size_t>(1, surface.width), rowsCount = (surface.state.size() + width - 1) / width;
  parallelFor(rowsCount, [&](size_t row) {
    for (size_t i = row * width; i < std::min(surface.state.size(), (row + 1) * width); ++i) {
      if (surface.state[i] == SurfaceState::Sky) continue;
      const bool hasNormal = surface.state[i] == SurfaceState::Matched;
      const glm::dvec3 p = surface.position[i], n = surface.normal[i];
      uint32_t count = 0;
      for (size_t l = 0; l < scene.lights.size(); ++l) {
        const Light& light = scene.lights[l];
        if (!light.castShadows) continue;  // visible without a ray
        glm::dvec3 toLight;
        if (light.type == LightType::Directional) {
          toLight = -axes[l];
        } else {
          const glm::dvec3 v = positions[l] - p;
          const double range = double(light.range);
          const double dist2 = glm::dot(v, v);
          if (!(dist2 > 0.0) || dist2 > 4.0 * range * range) continue;  // surely out of range: skip the root
          const double dist = glm::length(v);
          if (dist > range) continue;
          toLight = v / dist;
          if (light.type == LightType::Spot && glm::dot(-toLight, axes[l]) < cosOuter[l]) continue;
        }
        if (hasNormal && !(glm::dot(n, toLight) > 0.0)) continue;
        count++;
      }
      o.perPixel[i] = count;
    }
  });
  for (size_t i = 0; i < surface.state.size(); ++i) {
    if (surface.state[i] == SurfaceState::Sky) continue;
    if (surface.state[i] != SurfaceState::Matched) o.pixelsWithoutNormal++;
    o.total += o.perPixel[i];
  }
  return o;
}

double rayEfficiency(uint64_t oracle, uint64_t traced) { return traced == 0 ? 1.0 : double(oracle) / double(traced); }

}  // namespace hb
