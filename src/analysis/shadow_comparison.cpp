#include "analysis/shadow_comparison.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "analysis/analysis_pixels.h"
#include "base/errors.h"
#include "base/parallel.h"
#include "gpu/gpu_lights.h"
#include "shared/gpu_types.h"

namespace hb {

namespace {
constexpr double kEpsF = 1.0 / 16777216.0;  // 2^-24: unit roundoff of float

// One (pixel, light) pair repeated in double from the GPU's float inputs.
struct PairDecision {
  bool visible = false;
  bool traced = false;
  bool nearTie = false;
  glm::dvec3 dir{0.0};
  double tMax = 0;
};

PairDecision decidePair(const gpu::GpuLight& light, const glm::dvec3& p, const glm::dvec3& n, bool rangeTest,
                        double tMin, const Bvh& bvh) {
  PairDecision d;
  glm::dvec3 toLight;
  double magnitude;  // size of the float operands the GPU's toLight was formed from
  if (light.type == gpu::kLightDirectional) {
    toLight = -glm::dvec3(light.directionCosOuter);
    d.tMax = gpu::kDirectionalTMax;
    magnitude = 1.0;
  } else {
    const glm::dvec3 lp(light.positionRange);
    toLight = lp - p;
    d.tMax = glm::length(toLight);
    if (!(d.tMax > 0.0)) return d;  // at the light: no direction, no ray, not visible
    toLight /= d.tMax;
    // lp - p in float has absolute error <= eps (|lp| + |p|), i.e. relative to |toLight| that
    // much over tMax; the division and length add a few eps more.
    magnitude = 1.0 + (glm::length(lp) + glm::length(p)) / d.tMax;
    if (rangeTest) {
      const double range = light.positionRange.w;
      const double cone = glm::dot(-toLight, glm::dvec3(light.directionCosOuter));
      if (std::abs(d.tMax - range) <= 16.0 * kEpsF * (d.tMax + range) ||
          (light.type == gpu::kLightSpot && std::abs(cone - light.directionCosOuter.w) <= 16.0 * kEpsF * magnitude))
        d.nearTie = true;
      if (d.tMax > range || (light.type == gpu::kLightSpot && cone < light.directionCosOuter.w)) return d;
    }
  }
  if (glm::dot(n, n) > 0.0) {
    const double nl = glm::dot(n, toLight);
    // Both unit: the float dot product errs by <= 3 eps, plus the error of toLight (magnitude).
    if (std::abs(nl) <= 16.0 * kEpsF * magnitude) d.nearTie = true;
    if (nl <= 0.0) return d;
  }
  if (light.castShadows == 0u) {
    d.visible = true;
    return d;
  }
  d.traced = true;
  d.dir = toLight;
  d.visible = !bvh.occluded(p, toLight, tMin, d.tMax);
  return d;
}
}  // namespace

void ShadowComparison::addCounts(const ShadowComparison& o) {
  pairs += o.pairs;
  rays += o.rays;
  mismatches += o.mismatches;
  nearTie += o.nearTie;
  endpoint += o.endpoint;
  grazing += o.grazing;
}

ShadowComparison compareShadows(const Scene& scene, const Bvh& bvh, const ShadowReadback& shadows,
                                const CullingReadback& culling, uint32_t width, uint32_t height, uint32_t tileSize,
                                bool rangeTest, const glm::vec4& cameraPos) {
  const size_t pixels = size_t(width) * height;
  const uint32_t words = shadows.words;
  HB_ASSERT(shadows.visibility.size() == words * pixels && shadows.positions.size() == 4 * pixels &&
            shadows.normals.size() == 4 * pixels);
  const bool zbin = culling.lists == LightLists::Zbin;
  HB_ASSERT(!zbin || shadows.ranges.size() == pixels);
  const std::vector<gpu::GpuLight> lights = packLights(scene.lights);
  glm::vec3 lo, hi;
  scene.bounds(lo, hi);
  const double diagonal = glm::length(glm::dvec3(hi) - glm::dvec3(lo));
  ShadowComparison c;
  c.visibility.assign(words * pixels, 0u);
  std::vector<ShadowComparison> rows(height);  // counts per row, summed in row order
  parallelFor(height, [&](size_t yy) {
    const uint32_t y = uint32_t(yy);
    ShadowComparison& row = rows[y];
    for (uint32_t x = 0; x < width; ++x) {
      const size_t i = size_t(y) * width + x;
      auto gpuWord = [&](uint32_t j) { return shadows.visibility[size_t(j) * pixels + i]; };
      if (shadows.positions[4 * i + 3] != 1.0f) {  // sky: no pairs, word 0 must be 0
        row.mismatches += uint64_t(std::popcount(gpuWord(0)));
        continue;
      }
      const glm::vec3 pf(shadows.positions[4 * i], shadows.positions[4 * i + 1], shadows.positions[4 * i + 2]);
      const glm::dvec3 p(pf);
      const double tMin = gpu::shadowTMin(cameraPos, pf);  // as the GPU computed it, in float
      const glm::dvec3 n(shadows.normals[4 * i], shadows.normals[4 * i + 1], shadows.normals[4 * i + 2]);
      const uint32_t tile = tileIndexOf(culling, x, y, tileSize);
      const auto [first, last] = culling.pixelSlice(tile, zbin ? shadows.ranges[i] : 0u);
      const uint32_t count = last - first;
      HB_ASSERT((count + 31) / 32 <= std::max(words, 1u));
      // Bits past the walk's end in its last word must be 0 (words past it are never written).
      if (count % 32 != 0)
        row.mismatches += uint64_t(std::popcount(gpuWord(count / 32) & ~((1u << (count % 32)) - 1u)));
      if (count == 0) row.mismatches += uint64_t(std::popcount(gpuWord(0)));
      for (uint32_t k = 0; k < count; ++k) {
        const uint32_t li = culling.indices[first + k];
        HB_ASSERT(li < lights.size());
        const PairDecision d = decidePair(lights[li], p, n, rangeTest, tMin, bvh);
        row.pairs++;
        if (d.traced) row.rays++;
        const uint32_t bit = 1u << (k % 32);
        if (d.visible) c.visibility[size_t(k / 32) * pixels + i] |= bit;
        if (d.visible == bool(gpuWord(k / 32) & bit)) continue;
        row.mismatches++;
        if (d.nearTie) {
          row.nearTie++;
          continue;
        }
        if (!d.traced) continue;  // unexplained: a decision without a ray that is not a tie
        const double delta = kFloatRayShift * (glm::length(p) + std::min(d.tMax, diagonal));
        const bool wide = bvh.occluded(p, d.dir, std::max(0.0, tMin - delta), d.tMax + delta);
        const bool narrow = bvh.occluded(p, d.dir, tMin + delta, std::max(tMin + delta, d.tMax - delta));
        if (wide != narrow) {
          row.endpoint++;
          continue;
        }
        for (int axis = 0; axis < 6; ++axis) {
          glm::dvec3 shift(0.0);
          shift[axis / 2] = axis % 2 ? delta : -delta;
          if (bvh.occluded(p + shift, d.dir, tMin, d.tMax) == d.visible) {  // the answer flips
            row.grazing++;
            break;
          }
        }
      }
    }
  });
  for (const ShadowComparison& row : rows) c.addCounts(row);
  return c;
}

}  // namespace hb
