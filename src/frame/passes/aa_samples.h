// The standard sample positions of Vulkan (spec, "Multisampling", standard sample locations), in
// [0, 1)² of the pixel with y down, which the anti-aliasing of 3D rasterization samples
// (docs/methods/3d-rasterization.md "Anti-aliasing") and the raster pipeline's own multisampling
// uses where the device reports standardSampleLocations. shaders/shading_visbuffer.comp.glsl holds
// CSAA's 12 coverage positions (kCsaaCoverage below) as literals.
#pragma once
#include <cstdint>
#include <span>

#include <glm/glm.hpp>

#include "config/config.h"

namespace hb {

inline constexpr glm::vec2 kStdSamples4[4] = {{0.375f, 0.125f}, {0.875f, 0.375f}, {0.125f, 0.625f}, {0.625f, 0.875f}};
inline constexpr glm::vec2 kStdSamples8[8] = {{0.5625f, 0.3125f}, {0.4375f, 0.6875f}, {0.8125f, 0.5625f},
                                              {0.3125f, 0.1875f}, {0.1875f, 0.8125f}, {0.0625f, 0.4375f},
                                              {0.6875f, 0.9375f}, {0.9375f, 0.0625f}};
inline constexpr glm::vec2 kStdSamples16[16] = {
    {0.5625f, 0.5625f}, {0.4375f, 0.3125f}, {0.3125f, 0.625f}, {0.75f, 0.4375f}, {0.1875f, 0.375f}, {0.625f, 0.8125f},
    {0.8125f, 0.6875f}, {0.6875f, 0.1875f}, {0.375f, 0.875f},  {0.5f, 0.0625f},  {0.25f, 0.125f},   {0.125f, 0.75f},
    {0.0f, 0.5f},       {0.9375f, 0.25f},   {0.875f, 0.9375f}, {0.0625f, 0.0f}};
// CSAA 4 + 12: the 4 stored samples are the 4x pattern; the 12 coverage samples are the 16x
// pattern's last 12 (its first 4 lie within 0.19 px of the centre, close to the stored ones').
inline constexpr std::span<const glm::vec2> kCsaaCoverage{kStdSamples16 + 4, 12};

// The positions with a visibility entry of their own for `aa` (empty for none).
inline std::span<const glm::vec2> aaStoredPositions(AntiAliasing aa) {
  switch (aa) {
    case AntiAliasing::None: return {};
    case AntiAliasing::Msaa4:
    case AntiAliasing::Csaa4x12: return kStdSamples4;
    case AntiAliasing::Msaa8: return kStdSamples8;
    case AntiAliasing::Msaa16: return kStdSamples16;
  }
  return {};
}

}  // namespace hb
