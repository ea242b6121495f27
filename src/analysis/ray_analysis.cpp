#include "analysis/ray_analysis.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "base/errors.h"
#include "gpu/gpu_lights.h"
#include "shared/gpu_types.h"

namespace hb {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kEpsF = 1.0 / 16777216.0;  // 2^-24: unit roundoff of float
constexpr double kRadToDeg = 57.29577951308232;

bool isSky(float depth) { return !(depth > 0.0f); }

uint32_t tileIndexOf(const CullingReadback& c, uint32_t x, uint32_t y, uint32_t tileSize) {
  return (y / tileSize) * c.tilesX + x / tileSize;
}

// Angle between two unit vectors, accurate near 0 and pi (acos loses half the digits there).
double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}
}  // namespace

// ---- ray accounting ---------------------------------------------------------------------------

PixelAccount unpackAccount(uint32_t t) {
  auto field = [t](uint32_t shift) { return (t >> shift) & gpu::kAccountMask; };
  return {field(gpu::kAccountTracedShift), field(gpu::kAccountNormalShift), field(gpu::kAccountRangeShift),
          field(gpu::kAccountAtLightShift), field(gpu::kAccountNoShadowShift)};
}

uint64_t RayAccounting::bucketSum() const {
  return culledByTile + droppedByOverflow + culledByRange + culledByNormal + atLight + noShadow + traced;
}

RayAccounting accountRays(const ShadowReadback& shadows, const CullingReadback& culling,
                          const std::vector<float>& depth, uint32_t width, uint32_t height, uint32_t tileSize,
                          uint32_t sceneLightCount) {
  const size_t pixels = size_t(width) * height;
  HB_ASSERT(depth.size() == pixels && shadows.accounting.size() == pixels);
  HB_ASSERT(tileSize > 0 && culling.tilesX * tileSize >= width && culling.tilesY * tileSize >= height);
  HB_ASSERT(culling.total.size() == size_t(culling.tilesX) * culling.tilesY && culling.count.size() == culling.total.size());
  RayAccounting r;
  r.perPixel.assign(pixels, 0);
  r.histogram.assign(std::min(sceneLightCount, gpu::kMaxLightsPerTile) + 1, 0);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      const size_t i = size_t(y) * width + x;
      if (isSky(depth[i])) continue;
      const uint32_t tile = tileIndexOf(culling, x, y, tileSize);
      const uint32_t total = culling.total[tile], count = culling.count[tile];
      HB_ASSERT(count <= total && total <= sceneLightCount);
      const PixelAccount a = unpackAccount(shadows.accounting[i]);
      r.candidates += sceneLightCount;
      r.culledByTile += sceneLightCount - total;
      r.droppedByOverflow += total - count;
      r.culledByRange += a.byRange;
      r.culledByNormal += a.byNormal;
      r.atLight += a.atLight;
      r.noShadow += a.noShadow;
      r.traced += a.traced;
      r.perPixel[i] = a.traced;
      HB_ASSERT(a.traced < r.histogram.size());
      r.histogram[a.traced]++;
    }
  return r;
}

nlohmann::json toJson(const RayAccounting& r) {
  return {{"candidates", r.candidates},       {"culled_by_tile", r.culledByTile},
          {"dropped_by_overflow", r.droppedByOverflow}, {"culled_by_range", r.culledByRange},
          {"culled_by_normal", r.culledByNormal}, {"at_light", r.atLight},
          {"no_shadow", r.noShadow},           {"traced", r.traced},
          {"per_pixel_histogram", r.histogram}};
}

ImageRGBA8 rayHeatmap(const std::vector<uint32_t>& perPixel, uint32_t width, uint32_t height,
                      uint32_t sceneLightCount) {
  HB_ASSERT(perPixel.size() == size_t(width) * height);
  return heatmapThesis(perPixel, width, height, std::min(sceneLightCount, gpu::kMaxLightsPerTile));
}

// ---- reference surface ------------------------------------------------------------------------

ReferenceSurface referenceSurface(const Bvh& bvh, const std::vector<float>& depth,
                                  const ReconstructionCamera<double>& cam) {
  const size_t pixels = size_t(cam.width) * cam.height;
  HB_ASSERT(depth.size() == pixels);
  ReferenceSurface s;
  s.width = cam.width;
  s.height = cam.height;
  s.eye = glm::dvec3(cam.viewInv[3]);
  s.state.assign(pixels, SurfaceState::Sky);
  s.position.assign(pixels, glm::dvec3(0.0));
  s.normal.assign(pixels, glm::dvec3(0.0));
  for (uint32_t y = 0; y < cam.height; ++y)
    for (uint32_t x = 0; x < cam.width; ++x) {
      const size_t i = size_t(y) * cam.width + x;
      if (isSky(depth[i])) continue;
      // The eye ray through the pixel centre, scaled so that its view-space z step is -1: then
      // the ray parameter equals the view distance -z = D / (depth + C) (camera.h).
      const double ndcX = std::fma((x + 0.5) / cam.width, 2.0, -1.0);
      const double ndcY = std::fma((y + 0.5) / cam.height, 2.0, -1.0);
      const glm::dvec3 dir(cam.viewInv * glm::dvec4(ndcX / cam.a, ndcY / cam.b, -1.0, 0.0));
      const double tDepth = cam.d / (double(depth[i]) + cam.c);
      double t;
      uint32_t tri;
      // The window: kSurfaceMatchTolerance relative, plus the rasteriser's absolute error far from
      // the origin (vertex − eye cancels in float: ~16 u (|eye| + distance), doubled).
      const double window = kSurfaceMatchTolerance * tDepth + kSurfaceMatchFarTerm * (glm::length(s.eye) + tDepth);
      const bool hit = bvh.closestHit(s.eye, dir, std::max(0.0, tDepth - window), kInf, t, tri);
      if (hit && t <= tDepth + window) {
        const BvhTriangle& T = bvh.input(tri);
        s.position[i] = s.eye + t * dir;
        glm::dvec3 n = glm::normalize(glm::cross(T.v1 - T.v0, T.v2 - T.v0));
        if (glm::dot(n, s.eye - s.position[i]) < 0.0) n = -n;
        s.normal[i] = n;
        s.state[i] = SurfaceState::Matched;
        s.matched++;
      } else {
        s.position[i] = worldFromDepth<double>(cam, x, y, double(depth[i]));
        s.state[i] = SurfaceState::Unmatched;
        s.unmatched++;
      }
    }
  return s;
}

// ---- oracle -----------------------------------------------------------------------------------

OracleRays oracleRays(const Scene& scene, const ReferenceSurface& surface) {
  OracleRays o;
  o.perPixel.assign(surface.state.size(), 0);
  for (size_t i = 0; i < surface.state.size(); ++i) {
    if (surface.state[i] == SurfaceState::Sky) continue;
    const bool hasNormal = surface.state[i] == SurfaceState::Matched;
    if (!hasNormal) o.pixelsWithoutNormal++;
    const glm::dvec3 p = surface.position[i], n = surface.normal[i];
    uint32_t count = 0;
    for (const Light& light : scene.lights) {
      if (!light.castShadows) continue;  // visible without a ray
      const glm::dvec3 axis = glm::normalize(glm::dvec3(light.direction));
      glm::dvec3 toLight;
      if (light.type == LightType::Directional) {
        toLight = -axis;
      } else {
        const glm::dvec3 v = glm::dvec3(light.position) - p;
        const double dist = glm::length(v);
        if (!(dist > 0.0) || dist > double(light.range)) continue;
        toLight = v / dist;
        if (light.type == LightType::Spot && glm::dot(-toLight, axis) < std::cos(double(light.outerConeAngle)))
          continue;
      }
      if (hasNormal && !(glm::dot(n, toLight) > 0.0)) continue;
      count++;
    }
    o.perPixel[i] = count;
    o.total += count;
  }
  return o;
}

double rayEfficiency(uint64_t oracle, uint64_t traced) { return traced == 0 ? 1.0 : double(oracle) / double(traced); }

// ---- accuracy ---------------------------------------------------------------------------------

NormalAccuracy normalAccuracy(const std::vector<float>& normals, const ReferenceSurface& surface) {
  const size_t pixels = surface.state.size();
  HB_ASSERT(normals.size() == 4 * pixels);
  NormalAccuracy a;
  a.angleDeg.assign(pixels, 0.0f);
  std::vector<double> angles;
  double sumAngle = 0, sumImage = 0;
  for (size_t i = 0; i < pixels; ++i) {
    if (surface.state[i] == SurfaceState::Sky) continue;
    if (surface.state[i] == SurfaceState::Unmatched) {
      a.withoutReference++;
      continue;
    }
    const glm::dvec3 g(normals[4 * i], normals[4 * i + 1], normals[4 * i + 2]);
    const double len = glm::length(g);
    if (!(len > 0.0) || !std::isfinite(len)) {
      a.withoutReconstruction++;
      continue;
    }
    const glm::dvec3 gu = g / len, r = surface.normal[i];
    const double angle = angleBetween(gu, r) * kRadToDeg;
    angles.push_back(angle);
    a.angleDeg[i] = float(angle);
    sumAngle += angle;
    // |(g*0.5+0.5) - (r*0.5+0.5)| = 0.5 |g - r| per channel; mean over r, g, b.
    const glm::dvec3 d = glm::abs(gu - r) * 0.5;
    sumImage += (d.x + d.y + d.z) / 3.0;
  }
  a.compared = angles.size();
  if (a.compared > 0) {
    a.meanAngleDeg = sumAngle / double(a.compared);
    a.meanImageDifference = sumImage / double(a.compared);
    a.maxAngleDeg = *std::max_element(angles.begin(), angles.end());
    // Nearest-rank 95th percentile: the smallest value with at least 95 % of the samples <= it.
    const size_t rank = size_t(std::ceil(0.95 * double(a.compared))) - 1;
    std::nth_element(angles.begin(), angles.begin() + rank, angles.end());
    a.p95AngleDeg = angles[rank];
  }
  return a;
}

nlohmann::json toJson(const NormalAccuracy& a) {
  return {{"compared", a.compared},
          {"without_reconstruction", a.withoutReconstruction},
          {"without_reference", a.withoutReference},
          {"mean_angle_deg", a.meanAngleDeg},
          {"p95_angle_deg", a.p95AngleDeg},
          {"max_angle_deg", a.maxAngleDeg},
          {"mean_image_difference", a.meanImageDifference}};
}

PositionAccuracy positionAccuracy(const std::vector<float>& positions, const std::vector<float>& depth,
                                  const ReconstructionCamera<double>& cam) {
  const size_t pixels = size_t(cam.width) * cam.height;
  HB_ASSERT(depth.size() == pixels && positions.size() == 4 * pixels);
  PositionAccuracy a;
  a.relative.assign(pixels, 0.0f);
  const glm::dvec3 eye(cam.viewInv[3]);
  double sum = 0, sumPlain = 0;
  for (uint32_t y = 0; y < cam.height; ++y)
    for (uint32_t x = 0; x < cam.width; ++x) {
      const size_t i = size_t(y) * cam.width + x;
      if (isSky(depth[i])) continue;
      const glm::dvec3 g(positions[4 * i], positions[4 * i + 1], positions[4 * i + 2]);
      if (!std::isfinite(g.x) || !std::isfinite(g.y) || !std::isfinite(g.z)) {
        a.nonFinite++;
        continue;
      }
      const glm::dvec3 ref = worldFromDepth<double>(cam, x, y, double(depth[i]));
      const glm::dvec3 plain = worldFromDepthPlain<double>(cam, x, y, double(depth[i]));
      const double rel = glm::length(g - ref) / glm::length(ref - eye);
      const double relPlain = glm::length(g - plain) / glm::length(plain - eye);
      a.relative[i] = float(rel);
      a.maxRelative = std::max(a.maxRelative, rel);
      a.maxRelativePlain = std::max(a.maxRelativePlain, relPlain);
      sum += rel;
      sumPlain += relPlain;
      a.compared++;
    }
  if (a.compared > 0) {
    a.meanRelative = sum / double(a.compared);
    a.meanRelativePlain = sumPlain / double(a.compared);
  }
  return a;
}

nlohmann::json toJson(const PositionAccuracy& a) {
  return {{"compared", a.compared},
          {"max_relative", a.maxRelative},
          {"mean_relative", a.meanRelative},
          {"max_relative_plain", a.maxRelativePlain},
          {"mean_relative_plain", a.meanRelativePlain},
          {"non_finite", a.nonFinite}};
}

// ---- CPU shadow reference ---------------------------------------------------------------------

namespace {

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

ShadowComparison compareShadows(const Scene& scene, const Bvh& bvh, const ShadowReadback& shadows,
                                const CullingReadback& culling, uint32_t width, uint32_t height,
                                uint32_t tileSize, bool rangeTest, const glm::vec4& cameraPos) {
  const size_t pixels = size_t(width) * height;
  HB_ASSERT(shadows.visibility.size() == pixels && shadows.positions.size() == 4 * pixels &&
            shadows.normals.size() == 4 * pixels);
  const std::vector<gpu::GpuLight> lights = packLights(scene.lights);
  glm::vec3 lo, hi;
  scene.bounds(lo, hi);
  const double diagonal = glm::length(glm::dvec3(hi) - glm::dvec3(lo));
  ShadowComparison c;
  c.visibility.assign(pixels, 0u);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      const size_t i = size_t(y) * width + x;
      const uint32_t gpuMask = shadows.visibility[i];
      if (shadows.positions[4 * i + 3] != 1.0f) {  // sky: no pairs, the mask must be 0
        if (gpuMask != 0u) c.mismatches += uint64_t(__builtin_popcount(gpuMask));
        continue;
      }
      const glm::vec3 pf(shadows.positions[4 * i], shadows.positions[4 * i + 1], shadows.positions[4 * i + 2]);
      const glm::dvec3 p(pf);
      const double tMin = gpu::shadowTMin(cameraPos, pf);  // as the GPU computed it, in float
      const glm::dvec3 n(shadows.normals[4 * i], shadows.normals[4 * i + 1], shadows.normals[4 * i + 2]);
      const uint32_t tile = tileIndexOf(culling, x, y, tileSize);
      const uint32_t count = culling.count[tile], offset = culling.offset[tile];
      HB_ASSERT(count <= gpu::kMaxLightsPerTile);
      const uint32_t listMask = count == 32 ? ~0u : (1u << count) - 1u;
      if (gpuMask & ~listMask) c.mismatches += uint64_t(__builtin_popcount(gpuMask & ~listMask));
      uint32_t mask = 0;
      for (uint32_t k = 0; k < count; ++k) {
        const uint32_t li = culling.indices[offset + k];
        HB_ASSERT(li < lights.size());
        const PairDecision d = decidePair(lights[li], p, n, rangeTest, tMin, bvh);
        c.pairs++;
        if (d.traced) c.rays++;
        if (d.visible) mask |= 1u << k;
        if (d.visible == bool(gpuMask & (1u << k))) continue;
        c.mismatches++;
        if (d.nearTie) {
          c.nearTie++;
          continue;
        }
        if (!d.traced) continue;  // unexplained: a decision without a ray that is not a tie
        const double delta = kFloatRayShift * (glm::length(p) + std::min(d.tMax, diagonal));
        const bool wide = bvh.occluded(p, d.dir, std::max(0.0, tMin - delta), d.tMax + delta);
        const bool narrow = bvh.occluded(p, d.dir, tMin + delta, std::max(tMin + delta, d.tMax - delta));
        if (wide != narrow) {
          c.endpoint++;
          continue;
        }
        for (int axis = 0; axis < 6; ++axis) {
          glm::dvec3 shift(0.0);
          shift[axis / 2] = axis % 2 ? delta : -delta;
          if (bvh.occluded(p + shift, d.dir, tMin, d.tMax) == d.visible) {  // the answer flips
            c.grazing++;
            break;
          }
        }
      }
      c.visibility[i] = mask;
    }
  return c;
}

}  // namespace hb
