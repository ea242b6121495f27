#include "analysis/frame_rays.h"

#include "analysis/analysis_pixels.h"
#include "base/errors.h"

namespace hb {

namespace {

RayRecord rayOf(const glm::vec3& origin, float tMin, const glm::vec3& dir, float tMax) {
  return RayRecord{{origin.x, origin.y, origin.z}, tMin, {dir.x, dir.y, dir.z}, tMax};
}

// The stored world position of pixel i, or false where the shadow pass stored none (sky).
bool storedPosition(const ShadowReadback& s, size_t i, glm::vec3& p) {
  if (s.positions[4 * i + 3] != 1.0f) return false;
  p = glm::vec3(s.positions[4 * i], s.positions[4 * i + 1], s.positions[4 * i + 2]);
  return true;
}

}  // namespace

FrameRays frameShadowRays(const ShadowReadback& shadows, const CullingReadback& culling,
                          const std::vector<gpu::GpuLight>& lights, const glm::vec4& cameraPos, uint32_t width,
                          uint32_t height, uint32_t tileSize) {
  const size_t pixels = size_t(width) * height;
  HB_ASSERT(shadows.positions.size() == 4 * pixels && shadows.traced.size() == shadows.words * pixels);
  const bool zbin = culling.lists == LightLists::Zbin;
  HB_ASSERT(!zbin || shadows.ranges.size() == pixels);
  FrameRays out;
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      const size_t i = size_t(y) * width + x;
      glm::vec3 position;
      if (!storedPosition(shadows, i, position)) continue;
      // raybench_common.glsl.inc traceStored, line for line (float, the same operations).
      const float tMin = gpu::shadowTMin(cameraPos, position);
      const auto [first, last] =
          culling.pixelSlice(tileIndexOf(culling, x, y, tileSize), zbin ? shadows.ranges[i] : 0u);
      HB_ASSERT(last - first <= 32u * shadows.words);
      for (uint32_t k = 0; k < last - first; ++k) {
        if ((shadows.traced[size_t(k >> 5) * pixels + i] & (1u << (k & 31u))) == 0u) continue;
        const gpu::GpuLight& light = lights.at(culling.indices[first + k]);
        glm::vec3 dir;
        float tMax;
        if (light.type == gpu::kLightDirectional) {
          dir = -glm::vec3(light.directionCosOuter);
          tMax = gpu::kDirectionalTMax;
        } else {
          dir = glm::vec3(light.positionRange) - position;
          tMax = glm::length(dir);
          dir /= tMax;
        }
        out.rays.push_back(rayOf(position, tMin, dir, tMax));
        out.pixel.push_back(uint32_t(i));
      }
    }
  return out;
}

FrameRays frameAoRays(const ShadowReadback& shadows, const std::vector<glm::vec3>& directions,
                      const glm::vec4& cameraPos, float dMax, uint32_t width, uint32_t height) {
  const size_t pixels = size_t(width) * height;
  HB_ASSERT(shadows.positions.size() == 4 * pixels && shadows.normals.size() == 4 * pixels);
  const float tMax = dMax > 0.0f ? dMax : gpu::kDirectionalTMax;
  FrameRays out;
  for (size_t i = 0; i < pixels; ++i) {
    glm::vec3 x;
    if (!storedPosition(shadows, i, x)) continue;
    const glm::vec3 n(shadows.normals[4 * i], shadows.normals[4 * i + 1], shadows.normals[4 * i + 2]);
    if (!(glm::dot(n, n) > 0.0f)) continue;  // kAoNoNormal: no rays
    const float tMin = gpu::shadowTMin(cameraPos, x);
    // ao_common.glsl.inc, the ldm/raytraced loop: each direction into n's hemisphere.
    for (const glm::vec3& v : directions) {
      const float c = glm::dot(n, v);
      if (c == 0.0f) continue;
      out.rays.push_back(rayOf(x, tMin, c > 0.0f ? v : -v, tMax));
      out.pixel.push_back(uint32_t(i));
      out.weight.push_back(std::abs(c));
    }
  }
  return out;
}

}  // namespace hb
