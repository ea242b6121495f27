#include "analysis/culling_analysis.h"
#include "base/numbers.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "base/errors.h"
#include "base/parallel.h"
#include "frame/renderer.h"

namespace hb {

namespace {

uint32_t tilesX(const CullingInputs& in) { return tileCount(in.width, in.tileSize); }
uint32_t tilesY(const CullingInputs& in) { return tileCount(in.height, in.tileSize); }

void checkInputs(const CullingInputs& in) {
  HB_ASSERT(in.depth && in.lights && in.tileSize > 0 && in.capacity > 0);
  HB_ASSERT(in.depth->size() == size_t(in.width) * in.height);
}

// The double-precision view of everything: the float matrices are the camera (the depth image
// was rendered with them), converted exactly.
struct DoubleSetup {
  ProjectionParams<double> proj;
  std::vector<ViewLight<double>> lights;
};
DoubleSetup doubleSetup(const CullingInputs& in) {
  DoubleSetup s{projectionParams(glm::dmat4(in.proj)), {}};
  const glm::dmat4 view(in.view);
  for (const Light& l : *in.lights) s.lights.push_back(toViewLight(l, view));
  return s;
}

TileVolume<double> doubleVolume(const CullingInputs& in, const ProjectionParams<double>& proj, const TileRect& rect) {
  const TileDepthRange r = tileDepthRange(*in.depth, in.width, in.height, rect);
  return tileVolume(proj, rect, in.width, in.height, double(r.minDepth), double(r.maxDepth));
}

// A cheap, rigorous rejection before the exact test: the distance from a point to a convex
// polyhedron is at least its distance outside any face plane, so a sphere lying beyond a plane
// by more than the rounding slack misses the tile.
bool sphereClearlyOutside(const TileVolume<double>& tile, const ViewLight<double>& l) {
  double scale = glm::length(l.position) + l.range;
  for (const auto& c : tile.corners) scale = std::max(scale, glm::length(c));
  const double slack = 1e-12 * scale;  // thousands of double ulps of the coordinates
  for (const auto& p : tile.planes)
    if (glm::dot(p.n, l.position) + p.d < -(l.range + slack)) return true;
  return false;
}

// Does the light reach the view-space point p? Range ball, and for a spot its cone (an outer angle
// of 90° or more leaves the half-space or the ball: cosOuter <= 0 still reads right).
bool lightReachesPoint(const ViewLight<double>& l, const glm::dvec3& p) {
  if (l.type == LightType::Directional) return true;
  const glm::dvec3 v = p - l.position;
  const double d2 = glm::dot(v, v);
  if (d2 > l.range * l.range) return false;
  return l.type == LightType::Point || glm::dot(v, l.direction) >= l.cosOuter * std::sqrt(d2);
}

// The view-space points of the tile's non-sky pixels, at pixel centres, in double.
std::vector<glm::dvec3> tilePoints(const CullingInputs& in, const ProjectionParams<double>& proj,
                                   const TileRect& rect) {
  std::vector<glm::dvec3> pts;
  for (uint32_t y = rect.y0; y < rect.y1; ++y)
    for (uint32_t x = rect.x0; x < rect.x1; ++x) {
      const float d = (*in.depth)[size_t(y) * in.width + x];
      if (d <= 0.0f) continue;
      const double z = viewZFromDepth(double(d), proj);
      const double ndcX = 2.0 * ((x + 0.5) / in.width) - 1.0, ndcY = 2.0 * ((y + 0.5) / in.height) - 1.0;
      pts.emplace_back(ndcX / proj.a * -z, ndcY / proj.b * -z, z);
    }
  return pts;
}

}  // namespace

CullingReference cullingReference(const CullingInputs& in) {
  checkInputs(in);
  const uint32_t tx = tilesX(in), ty = tilesY(in);
  const size_t n = in.lights->size();
  const DoubleSetup dbl = doubleSetup(in);
  const ProjectionParams<float> projF = projectionParams(in.proj);
  std::vector<ViewLight<float>> lightsF;
  for (const Light& l : *in.lights) lightsF.push_back(toViewLight(l, in.view));

  CullingReference ref;
  ref.same.resize(size_t(tx) * ty);
  ref.sameAll.resize(size_t(tx) * ty);
  ref.exact.resize(size_t(tx) * ty);
  ref.needed.resize(size_t(tx) * ty);
  // Every tile on every core; each writes only its own entries.
  parallelFor(size_t(tx) * ty, [&](size_t t) {
    const uint32_t x = uint32_t(t % tx), y = uint32_t(t / tx);
    const TileRect rect = tileRect(x, y, in.tileSize, in.width, in.height);
    const TileDepthRange range = tileDepthRange(*in.depth, in.width, in.height, rect);
    std::vector<uint32_t>& all = ref.sameAll[t];
    if (in.lightCulling) {
      auto volF = tileVolume(projF, rect, in.width, in.height, range.minDepth, range.maxDepth);
      applyDepthSlices(volF, in.depthSlices, projF, *in.depth, in.width, in.height, rect);
      all = cullTile(volF, lightsF, in.aabb, std::numeric_limits<uint32_t>::max()).indices;
    } else {
      for (uint32_t i = 0; i < n; ++i) all.push_back(i);  // every tile, sky included, as the GPU
    }
    TileLightList& stored = ref.same[t];
    stored.total = uint32_t(all.size());
    stored.indices.assign(all.begin(), all.begin() + std::min<size_t>(all.size(), in.capacity));

    const auto volD = tileVolume(dbl.proj, rect, in.width, in.height, double(range.minDepth), double(range.maxDepth));
    if (volD.empty) return;
    for (uint32_t i = 0; i < n; ++i) {
      const auto& l = dbl.lights[i];
      if (l.type != LightType::Directional && sphereClearlyOutside(volD, l)) continue;
      if (exactLightMeetsTile(volD, l)) ref.exact[t].push_back(i);
    }
    if (ref.exact[t].empty()) return;
    const std::vector<glm::dvec3> pts = tilePoints(in, dbl.proj, rect);
    for (uint32_t i : ref.exact[t])
      if (std::any_of(pts.begin(), pts.end(), [&](const glm::dvec3& p) { return lightReachesPoint(dbl.lights[i], p); }))
        ref.needed[t].push_back(i);
  });
  return ref;
}

std::vector<TileLightList> gpuTileLists(const CullingInputs& in, const CullingReadback& gpu) {
  checkInputs(in);
  HB_ASSERT(gpu.tilesX == tilesX(in) && gpu.tilesY == tilesY(in));
  const size_t tiles = size_t(gpu.tilesX) * gpu.tilesY;
  HB_ASSERT(gpu.offset.size() == tiles && gpu.count.size() == tiles && gpu.total.size() == tiles);
  std::vector<TileLightList> lists(tiles);
  for (size_t t = 0; t < tiles; ++t) {
    HB_ASSERT(uint64_t(gpu.offset[t]) + gpu.count[t] <= gpu.indices.size());
    lists[t].indices.assign(gpu.indices.begin() + gpu.offset[t], gpu.indices.begin() + gpu.offset[t] + gpu.count[t]);
    std::sort(lists[t].indices.begin(), lists[t].indices.end());
    lists[t].total = gpu.total[t];
  }
  return lists;
}

CullStatistics gpuCullStatistics(const CullingInputs& in, const CullingReadback& gpu, const CullingReference& ref) {
  const std::vector<TileLightList> lists = gpuTileLists(in, gpu);
  CullStatistics s = cullStatistics(lists, ref.exact, in.width, in.height, in.tileSize, in.capacity);
  addGeometryStatistics(s, lists, ref.needed, in.lightCulling && in.depthSlices > 0);
  return s;
}

ImageRGBA8 lightsPerTileHeatmap(const CullingInputs& in, const CullingReadback& gpu) {
  checkInputs(in);
  HB_ASSERT(gpu.tilesX == tilesX(in) && gpu.total.size() == size_t(gpu.tilesX) * gpu.tilesY);
  std::vector<uint32_t> counts(size_t(in.width) * in.height);
  for (uint32_t y = 0; y < in.height; ++y)
    for (uint32_t x = 0; x < in.width; ++x)
      counts[size_t(y) * in.width + x] = gpu.total[size_t(y / in.tileSize) * gpu.tilesX + x / in.tileSize];
  return heatmapThesis(counts, in.width, in.height, uint32_t(in.lights->size()));
}

nlohmann::json cullStatisticsJson(const CullStatistics& s, const CullingInputs& in) {
  return {{"tiles", s.tiles},
          {"lights_per_tile_mean", s.meanLightsPerTile},
          {"lights_per_tile_max", s.maxLightsPerTile},
          {"overflow_tiles", s.overflowTiles},
          {"false_positive_rate", s.falsePositiveRate},
          {"false_positives", s.falsePositives},
          {"false_negatives", s.falseNegatives},
          {"dropped_by_overflow", s.droppedByOverflow},
          {"memory_bytes", s.memoryBytes},
          {"tile_size", in.tileSize},
          {"aabb", in.aabb},
          {"light_culling", in.lightCulling},
          {"depth_slices", in.depthSlices},
          {"needed_pairs", s.neededPairs},
          {"geometry_false_positive_rate", s.uselessRate},
          {"geometry_false_negatives", s.missedNeeded},
          {"sliced_away", s.slicedAway}};
}

// ---- rounding margin --------------------------------------------------------------------------

double cullingDecisionMargin(const TileVolume<double>& tile, const ViewLight<double>& l, bool aabb) {
  if (l.type == LightType::Directional) return std::numeric_limits<double>::infinity();
  double closest = std::numeric_limits<double>::infinity();
  const bool cone = l.type == LightType::Spot && l.tanOuter >= 0.0;
  const double rBase = cone ? l.range * l.tanOuter : 0.0;
  for (const auto& p : tile.planes) {
    const double s = glm::dot(p.n, l.position) + p.d;
    closest = std::min(closest, std::abs(s + l.range));  // sphereOutsidePlane
    if (!cone) continue;
    closest = std::min(closest, std::abs(s));  // coneOutsidePlane: the tip
    const glm::dvec3 v = glm::cross(glm::cross(l.direction, p.n), l.direction);
    glm::dvec3 q = l.position + l.direction * l.range;
    if (glm::dot(v, v) > 0.0) q += glm::normalize(v) * rBase;
    closest = std::min(closest, std::abs(glm::dot(p.n, q) + p.d));  // coneOutsidePlane: Q
  }
  if (aabb) {
    const glm::dvec3 e = glm::max(glm::max(tile.aabbMin - l.position, l.position - tile.aabbMax), glm::dvec3(0.0));
    closest = std::min(closest, std::abs(glm::length(e) - l.range));
  }
  return closest;
}

// How far float evaluation can move any comparison of the culling test away from its double
// value, on the CPU (cull_ref.h<float>) or on the GPU (culling.glsl.inc).
//
// CPU float, correctly rounded ops: cull_ref_test.cpp (FloatAgreesWithDoubleExceptWithinRounding
// Margin) derives (21·cond + 32)·u·S for lights given in view space, with cond = the largest
// |p||q|/|cross(p, q)| over adjacent corner rays (small tiles: nearly parallel rays), R = the
// largest |ray component| (>= 1) and S = |centre| + range·(1 + max(tanOuter, 0)) + 2R·|zFar|.
//
// GPU: Vulkan only requires +, -, * to be correctly rounded; division may be off by 2.5 ulp
// (= 5u) and sqrt/inversesqrt by 2 ulp plus a reciprocal. Redoing that derivation with 5u per
// division and sqrt: a ray component has 2 divisions → 14u·R (was 6u); the side normal's cross
// product then carries 2·14√2 + 2 ≤ 42 u·|p||q| → 42u·cond, and its normalisation (sqrt + divide)
// 10u; near/far z = -D/(d + C) 8u·|z|; AABB corners (14√2 + 8 + 1)u·R|z| ≤ 30u·R|z|, covered by
// 2R|zFar| in S at 16u; the cone's extra terms 16u. Every constant at most doubles: 64u·S.
//
// View transform (not in the CPU test, whose lights start in view space): both sides compute
// view * (p, 1) in float, a 4-term dot product per component, |error| ≤ 4u·(Σ|V_ij||p_j| + |t_i|)
// ≤ 4u(|p| + |t|) (a row of a rotation has unit length), so ≤ 4√3u ≤ 7u·(|p_world| + |t|) in
// length, moving every signed distance by as much: 8u·(|p_world| + |t|). The axis mat3(view)*dir
// (3-term dots, 3√3u) plus the packer's extra float normalize (2u) and the GPU's normalize (10u)
// turn it by at most 16u rad, moving Q by 16u·(range + rBase) ≤ 16u·S.
//
// Total: bound = (42·cond + 80)·u·S + 8u·(|p_world| + |t|). Both the GPU and the CPU float stay
// within it of double, so where they disagree, double's margin is within it of zero.
double cullingRoundingBound(const std::array<glm::dvec3, 4>& rays, const TileVolume<double>& tile,
                            const ViewLight<double>& l, double worldPositionLength, double viewTranslationLength) {
  double cond = 0.0, bigR = 1.0;
  for (int k = 0; k < 4; ++k) {
    const glm::dvec3 p = rays[k], q = rays[(k + 1) % 4];
    cond = std::max(cond, glm::length(p) * glm::length(q) / glm::length(glm::cross(p, q)));
    bigR = std::max({bigR, std::abs(p.x), std::abs(p.y)});
  }
  const double rBase = l.range * std::max(l.tanOuter, 0.0);
  const double scale = glm::length(l.position) + l.range + rBase + 2.0 * bigR * std::abs(tile.zFar);
  return (42.0 * cond + 80.0) * kU * scale + 8.0 * kU * (worldPositionLength + viewTranslationLength);
}

double sliceDecisionMargin(const TileVolume<double>& tile, const ViewLight<double>& l,
                           const ProjectionParams<double>& proj, const std::vector<float>& depth, uint32_t width,
                           const TileRect& rect) {
  const double inf = std::numeric_limits<double>::infinity();
  if (l.type == LightType::Directional || tile.slices == 0 || tile.empty || !(tile.sliceScale > 0.0)) return inf;
  const double width1 = 1.0 / tile.sliceScale;  // one slab, in metres of z
  auto boundary = [&](double k) { return tile.zNear - k * width1; };
  // Distance from z to the nearest of the slices + 1 boundaries zNear - k·width1, k = 0..slices.
  auto toNearestBoundary = [&](double z) {
    const double k = std::clamp(std::round((tile.zNear - z) * tile.sliceScale), 0.0, double(tile.slices));
    return std::abs(z - boundary(k));
  };
  const double reach = l.range + sliceWidening(tile, l);
  double m = std::min(toNearestBoundary(l.position.z + reach), toNearestBoundary(l.position.z - reach));
  const double lo = sliceOf(tile, l.position.z + reach), hi = sliceOf(tile, l.position.z - reach);
  for (uint32_t y = rect.y0; y < rect.y1; ++y)
    for (uint32_t x = rect.x0; x < rect.x1; ++x) {
      const float d = depth[size_t(y) * width + x];
      if (d <= 0.0f) continue;
      const double z = viewZFromDepth(double(d), proj);
      m = std::min({m, std::abs(z - boundary(lo)), std::abs(z - boundary(hi + 1.0))});
    }
  return m;
}

// The slab test compares, in effect, view z values with the boundaries zNear - k/scale. Against
// double, float evaluation moves (u = 2^-24; GPU division 2.5 ulp = 5u):
//  - a pixel's z = -D/(d + C): (1 + u)(1 + 5u) → 6u·|z| <= 6u·|zFar|;
//  - zNear, zFar the same way, 6u each; scale = slices/(zNear - zFar) then carries the relative
//    error 6u(|zNear| + |zFar|)/(zNear - zFar) + u (subtraction) + 5u (division), which moves
//    boundary k = zNear - k/scale (k <= slices) by at most 6u(|zNear| + |zFar|) + 6u(zNear - zFar)
//    <= 12u(|zNear| + |zFar|), plus 6u·|zNear| for zNear itself and u·slices/scale = u(zNear -
//    zFar) for the product (zNear - z)·scale: under 20u(|zNear| + |zFar|);
//  - the light's ends zc ± (r + w): zc within 8u·worldScale (view transform, as in the plane
//    bound below), two sums 2u(|zc| + r + w), w itself is tiny (16u·(...)) and rounds at u·w.
// Summed and doubled for safety: 32u(|zNear| + |zFar| + |zc| + r) + 16u·worldScale.
double sliceRoundingBound(const TileVolume<double>& tile, const ViewLight<double>& l) {
  return 32.0 * kU * (std::abs(tile.zNear) + std::abs(tile.zFar) + std::abs(l.position.z) + l.range) +
         16.0 * kU * l.worldScale;
}

// ---- comparison -------------------------------------------------------------------------------

CullingComparison compareGpuToReference(const CullingInputs& in, const CullingReadback& gpu,
                                        const CullingReference& ref) {
  checkInputs(in);
  const uint32_t tx = tilesX(in), ty = tilesY(in);
  const size_t tiles = size_t(tx) * ty;
  HB_ASSERT(gpu.tilesX == tx && gpu.tilesY == ty && gpu.offset.size() == tiles && gpu.count.size() == tiles &&
            gpu.total.size() == tiles && ref.sameAll.size() == tiles);
  const DoubleSetup dbl = doubleSetup(in);
  const double viewT = glm::length(glm::dvec3(in.view[3]));
  std::vector<double> worldLen;
  for (const Light& l : *in.lights) worldLen.push_back(glm::length(glm::dvec3(l.position)));

  CullingComparison cmp;
  for (uint32_t y = 0; y < ty; ++y)
    for (uint32_t x = 0; x < tx; ++x) {
      const size_t t = size_t(y) * tx + x;
      const uint32_t count = gpu.count[t], total = gpu.total[t];
      const bool stride = gpu.lists == LightLists::Tile;  // the masks' lists are packed one after another
      if (count > in.capacity || count != std::min(total, in.capacity) ||
          (stride && gpu.offset[t] != t * in.capacity) || uint64_t(gpu.offset[t]) + count > gpu.indices.size()) {
        ++cmp.malformedTiles;
        continue;
      }
      std::vector<uint32_t> g(gpu.indices.begin() + gpu.offset[t], gpu.indices.begin() + gpu.offset[t] + count);
      std::sort(g.begin(), g.end());
      if (std::adjacent_find(g.begin(), g.end()) != g.end() || (!g.empty() && g.back() >= in.lights->size())) {
        ++cmp.malformedTiles;
        continue;
      }
      const std::vector<uint32_t>& f = ref.sameAll[t];
      const bool gpuOverflow = total > count;

      // Lazily: the tile's double volume, and the margin/bound of one light in it.
      const TileRect rect = tileRect(x, y, in.tileSize, in.width, in.height);
      bool haveVolume = false;
      TileVolume<double> vol{};
      std::array<glm::dvec3, 4> rays{};
      auto judge = [&](uint32_t i, bool gpuKept) {
        CullingMismatch m{uint32_t(t), i, gpuKept, false, std::numeric_limits<double>::infinity(), 0.0};
        if (in.lightCulling) {  // culling off involves no arithmetic: every disagreement is hard
          if (!haveVolume) {
            vol = doubleVolume(in, dbl.proj, rect);
            applyDepthSlices(vol, in.depthSlices, dbl.proj, *in.depth, in.width, in.height, rect);
            rays = tileCornerRays(dbl.proj, rect, in.width, in.height);
            haveVolume = true;
          }
          m.margin = cullingDecisionMargin(vol, dbl.lights[i], in.aabb);
          m.bound = cullingRoundingBound(rays, vol, dbl.lights[i], worldLen[i], viewT);
          m.borderline = !vol.empty && m.margin <= m.bound;
          if (in.depthSlices > 0 && !m.borderline) {
            const double sm = sliceDecisionMargin(vol, dbl.lights[i], dbl.proj, *in.depth, in.width, rect);
            const double sb = sliceRoundingBound(vol, dbl.lights[i]);
            if (sm <= sb) {
              m.margin = sm;
              m.bound = sb;
              m.borderline = true;
            }
          }
        }
        return m;
      };

      for (uint32_t i : g)
        if (!std::binary_search(f.begin(), f.end(), i)) cmp.mismatches.push_back(judge(i, true));
      for (uint32_t i : f) {
        // Above the last stored index of an overflowing GPU tile: kept or not, it is not stored.
        if (gpuOverflow && (g.empty() || i > g.back())) break;
        if (!std::binary_search(g.begin(), g.end(), i)) cmp.mismatches.push_back(judge(i, false));
      }
      // Totals: every flipped decision changes the total by one, so they differ by at most the
      // number of lights whose decision is borderline in this tile.
      if (total != f.size()) {
        const uint64_t diff = total > f.size() ? total - f.size() : f.size() - total;
        uint64_t borderline = 0;
        for (uint32_t i = 0; i < in.lights->size() && borderline < diff; ++i) borderline += judge(i, true).borderline;
        if (borderline < diff) ++cmp.totalMismatchTiles;
      }
    }
  for (const auto& m : cmp.mismatches) ++(m.borderline ? cmp.borderlineMismatches : cmp.hardMismatches);
  return cmp;
}

uint64_t zbinMissedPairs(const CullingInputs& in, const CullingReadback& gpu, const std::vector<uint32_t>& ranges) {
  checkInputs(in);
  HB_ASSERT(gpu.lists == LightLists::Zbin && ranges.size() == size_t(in.width) * in.height);
  const DoubleSetup dbl = doubleSetup(in);
  std::vector<uint64_t> rows(in.height, 0);
  parallelFor(in.height, [&](size_t yy) {
    const uint32_t y = uint32_t(yy);
    for (uint32_t x = 0; x < in.width; ++x) {
      const size_t i = size_t(y) * in.width + x;
      const float depth = (*in.depth)[i];
      if (!(depth > 0.0f)) continue;
      const double z = viewZFromDepth(double(depth), dbl.proj);
      const double ndcX = 2.0 * ((x + 0.5) / in.width) - 1.0, ndcY = 2.0 * ((y + 0.5) / in.height) - 1.0;
      const glm::dvec3 p(ndcX / dbl.proj.a * -z, ndcY / dbl.proj.b * -z, z);
      const uint32_t tile = (y / in.tileSize) * gpu.tilesX + x / in.tileSize;
      const auto [first, last] = gpu.pixelSlice(tile, ranges[i]);
      for (uint32_t k = gpu.offset[tile]; k < gpu.offset[tile] + gpu.count[tile]; ++k)
        if ((k < first || k >= last) && lightReachesPoint(dbl.lights[gpu.indices[k]], p)) rows[y]++;
    }
  });
  uint64_t missed = 0;
  for (uint64_t r : rows) missed += r;
  return missed;
}

CullingAnalysis analyzeCulling(const CullingInputs& in, const CullingReadback& gpu) {
  CullingAnalysis a;
  a.reference = cullingReference(in);
  a.stats = gpuCullStatistics(in, gpu, a.reference);
  a.comparison = compareGpuToReference(in, gpu, a.reference);
  a.heatmap = lightsPerTileHeatmap(in, gpu);
  a.json = cullStatisticsJson(a.stats, in);
  a.json["hard_mismatches"] = a.comparison.hardMismatches;
  a.json["borderline_mismatches"] = a.comparison.borderlineMismatches;
  return a;
}

}  // namespace hb
