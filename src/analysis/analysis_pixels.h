// Pixel helpers shared by the CPU analyses of a shadow frame (ray_analysis.h).
#pragma once
#include <cstdint>

#include "frame/renderer.h"

namespace hb {

// Depth 0 (reverse-Z: nothing rasterised) or not a number.
inline bool isSky(float depth) { return !(depth > 0.0f); }

// The light-culling tile of pixel (x, y). Precondition: culling is the grid of this tileSize.
inline uint32_t tileIndexOf(const CullingReadback& c, uint32_t x, uint32_t y, uint32_t tileSize) {
  return (y / tileSize) * c.tilesX + x / tileSize;
}

}  // namespace hb
