// Where every candidate (pixel, light) pair of a shadow frame went (docs/methods/thesis.md "Accuracy"), and its
// heatmaps. Images are row-major, width × height, top row first; depth 0 = sky.
#pragma once
#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "base/image_io.h"
#include "frame/renderer.h"

namespace hb {

// One pixel's accounting texel (4 words, gpu_types.h kAccount*), unpacked.
struct PixelAccount {
  uint32_t traced = 0, listed = 0, byNormal = 0, byRange = 0, atLight = 0, noShadow = 0;
};
PixelAccount unpackAccount(const uint32_t* texel);

// Totals over the non-sky pixels. Every candidate pair lands in exactly one bucket:
//   candidates = culledByTile + droppedByOverflow + culledByZbin + culledByRange + culledByNormal
//                + atLight + noShadow + traced.
struct RayAccounting {
  uint64_t candidates = 0;         // non-sky pixels × scene lights
  uint64_t culledByTile = 0;       // per pixel: scene lights − its tile's total
  uint64_t droppedByOverflow = 0;  // per pixel: tile total − tile count (capacity exceeded; tile lists only)
  uint64_t culledByZbin = 0;       // per pixel: its tile's lights outside its z-bin's range (zbin only)
  uint64_t culledByRange = 0, culledByNormal = 0, atLight = 0, noShadow = 0, traced = 0;
  // Pixels whose GPU walk visited another number of lights than the readback's slice: must be 0.
  uint64_t walkMismatches = 0;
  std::vector<uint32_t> perPixel;   // traced rays per pixel (0 for sky), width*height
  std::vector<uint64_t> histogram;  // [k] = non-sky pixels that traced k rays; size = the most + 1
  uint64_t bucketSum() const;
  void addCounts(const RayAccounting& other);  // every count (not perPixel, histogram)
  bool addsUp() const { return candidates == bucketSum() && walkMismatches == 0; }
};

// Preconditions: depth has width*height entries, shadows.accounting 4 per pixel; culling is the
// grid the shadow pass read (tilesX = ceil(width / tileSize), …); every tile total <= sceneLightCount.
RayAccounting accountRays(const ShadowReadback& shadows, const CullingReadback& culling,
                          const std::vector<float>& depth, uint32_t width, uint32_t height, uint32_t tileSize,
                          uint32_t sceneLightCount);
// Keys: candidates, culled_by_tile, dropped_by_overflow, culled_by_zbin, culled_by_range,
// culled_by_normal, at_light, no_shadow, traced, walk_mismatches, per_pixel_histogram.
nlohmann::json toJson(const RayAccounting& rays);

// Heatmap of per-pixel ray counts in the thesis's colours (image_io.h heatmapThesis); red =
// maxValue (rayHeatmapMax).
ImageRGBA8 rayHeatmap(const std::vector<uint32_t>& perPixel, uint32_t width, uint32_t height, uint32_t maxValue);
// Red of the ray heatmaps: capped tile lists min(sceneLightCount, 32), the most rays a pixel can
// trace; uncapped lists the most any pixel of `perPixel` traced (at least 1).
uint32_t rayHeatmapMax(bool capped, uint32_t sceneLightCount, const std::vector<uint32_t>& perPixel);

}  // namespace hb
