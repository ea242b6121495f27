#include "analysis/ray_accounting.h"

#include <algorithm>

#include "analysis/analysis_pixels.h"
#include "base/errors.h"
#include "base/parallel.h"
#include "shared/gpu_types.h"

namespace hb {

PixelAccount unpackAccount(const uint32_t* t) {
  return {t[0] & gpu::kAccountMask, t[0] >> 16, t[1] & gpu::kAccountMask, t[1] >> 16,
          t[2] & gpu::kAccountMask, t[2] >> 16};
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

uint64_t RayAccounting::bucketSum() const {
  return culledByTile + droppedByOverflow + culledByZbin + culledByRange + culledByNormal + atLight + noShadow + traced;
}

RayAccounting accountRays(const ShadowReadback& shadows, const CullingReadback& culling,
                          const std::vector<float>& depth, uint32_t width, uint32_t height, uint32_t tileSize,
                          uint32_t sceneLightCount) {
  const size_t pixels = size_t(width) * height;
  HB_ASSERT(depth.size() == pixels && shadows.accounting.size() == 4 * pixels);
  HB_ASSERT(tileSize > 0 && culling.tilesX * tileSize >= width && culling.tilesY * tileSize >= height);
  HB_ASSERT(culling.total.size() == size_t(culling.tilesX) * culling.tilesY &&
            culling.count.size() == culling.total.size());
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
  return {{"candidates", r.candidates},
          {"culled_by_tile", r.culledByTile},
          {"dropped_by_overflow", r.droppedByOverflow},
          {"culled_by_zbin", r.culledByZbin},
          {"culled_by_range", r.culledByRange},
          {"culled_by_normal", r.culledByNormal},
          {"at_light", r.atLight},
          {"no_shadow", r.noShadow},
          {"traced", r.traced},
          {"walk_mismatches", r.walkMismatches},
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

}  // namespace hb
