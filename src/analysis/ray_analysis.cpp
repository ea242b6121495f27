#include "analysis/ray_analysis.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "base/errors.h"
#include "base/parallel.h"
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

PixelAccount unpackAccount(const uint32_t* t) {
  return {t[0] & gpu::kAccountMask, t[0] >> 16,         t[1] & gpu::kAccountMask,
          t[1] >> 16,             t[2] & gpu::kAccountMask, t[2] >> 16};
}

void RayAccounting::addCounts(const RayAccounting& o) {
  candidates += o.candidates;
  culledByTile += o.culledByTile;
  droppedByOverflow += o.droppedByOverflow;
  culledByZbin += o.culledByZbin;
  culledByRange += o.culledByRange;
  culledByNormal += o.culledByNormal;
  atLight += o.atLight;
  noShadow += o.noShadow;
  traced += o.traced;
  walkMismatches += o.walkMismatches;
}

void ShadowComparison::addCounts(const ShadowComparison& o) {
  pairs += o.pairs;
  rays += o.rays;
  mismatches += o.mismatches;
  nearTie += o.nearTie;
  endpoint += o.endpoint;
  grazing += o.grazing;
}

uint64_t RayAccounting::bucketSum() const {
  return culledByTile + droppedByOverflow + culledByZbin + culledByRange + culledByNormal + atLight + noShadow + traced;
}

RayAccounting accountRays(const ShadowReadback& shadows, const CullingReadback& culling,
                          const std::vector<float>& depth, uint32_t width, uint32_t height, uint32_t tileSize,
                          uint32_t sceneLightCount) {
  const size_t pixels = size_t(width) * height;
  HB_ASSERT(depth.size() == pixels && shadows.accounting.size() == 4 * pixels);
  HB_ASSERT(tileSize > 0 && culling.tilesX * tileSize >= width && culling.tilesY * tileSize >= height);
  HB_ASSERT(culling.total.size() == size_t(culling.tilesX) * culling.tilesY && culling.count.size() == culling.total.size());
  const bool zbin = culling.lists == LightLists::Zbin;
  HB_ASSERT(!zbin || shadows.ranges.size() == pixels);
  RayAccounting r;
  r.perPixel.assign(pixels, 0);
  // One partial per row, summed in row order (integers: any order gives the same totals).
  std::vector<RayAccounting> rows(height);
  parallelFor(height, [&](size_t y) {
    RayAccounting& row = rows[y];
    for (uint32_t x = 0; x < width; ++x) {
      const size_t i = size_t(y) * width + x;
      if (isSky(depth[i])) continue;
      const uint32_t tile = tileIndexOf(culling, x, uint32_t(y), tileSize);
      const uint32_t total = culling.total[tile], count = culling.count[tile];
      HB_ASSERT(count <= total && total <= sceneLightCount);
      const auto [first, last] = culling.pixelSlice(tile, zbin ? shadows.ranges[i] : 0u);
      const PixelAccount a = unpackAccount(&shadows.accounting[4 * i]);
      row.candidates += sceneLightCount;
      row.culledByTile += sceneLightCount - total;
      row.droppedByOverflow += total - count;
      row.culledByZbin += count - (last - first);
      if (a.listed != last - first) row.walkMismatches++;
      row.culledByRange += a.byRange;
      row.culledByNormal += a.byNormal;
      row.atLight += a.atLight;
      row.noShadow += a.noShadow;
      row.traced += a.traced;
      r.perPixel[i] = a.traced;
    }
  });
  for (const RayAccounting& row : rows) r.addCounts(row);
  uint32_t most = 0;
  for (size_t i = 0; i < pixels; ++i)
    if (!isSky(depth[i])) most = std::max(most, r.perPixel[i]);
  r.histogram.assign(size_t(most) + 1, 0);
  for (size_t i = 0; i < pixels; ++i)
    if (!isSky(depth[i])) r.histogram[r.perPixel[i]]++;
  return r;
}

nlohmann::json toJson(const RayAccounting& r) {
  return {{"candidates", r.candidates},       {"culled_by_tile", r.culledByTile},
          {"dropped_by_overflow", r.droppedByOverflow}, {"culled_by_zbin", r.culledByZbin},
          {"culled_by_range", r.culledByRange}, {"culled_by_normal", r.culledByNormal},
          {"at_light", r.atLight},             {"no_shadow", r.noShadow},
          {"traced", r.traced},                {"walk_mismatches", r.walkMismatches},
          {"per_pixel_histogram", r.histogram}};
}

ImageRGBA8 rayHeatmap(const std::vector<uint32_t>& perPixel, uint32_t width, uint32_t height, uint32_t maxValue) {
  HB_ASSERT(perPixel.size() == size_t(width) * height);
  return heatmapThesis(perPixel, width, height, maxValue);
}

uint32_t rayHeatmapMax(bool capped, uint32_t sceneLightCount, const std::vector<uint32_t>& perPixel) {
  if (capped) return std::min(sceneLightCount, gpu::kMaxLightsPerTile);
  uint32_t most = 1;
  for (uint32_t v : perPixel) most = std::max(most, v);
  return most;
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
  parallelFor(cam.height, [&](size_t row) {
    const uint32_t y = uint32_t(row);
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
      } else {
        s.position[i] = worldFromDepth<double>(cam, x, y, double(depth[i]));
        s.state[i] = SurfaceState::Unmatched;
      }
    }
  });
  for (SurfaceState st : s.state) {
    s.matched += st == SurfaceState::Matched;
    s.unmatched += st == SurfaceState::Unmatched;
  }
  return s;
}

// ---- oracle -----------------------------------------------------------------------------------

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
      if (count % 32 != 0) row.mismatches += uint64_t(std::popcount(gpuWord(count / 32) & ~((1u << (count % 32)) - 1u)));
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
