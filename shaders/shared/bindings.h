// Descriptor bindings (set 0) of the passes, each written once here and used by the pass's shaders
// (layout(binding = k...)) and its C++ (the set layout and the descriptor writes). A pass moves
// its bindings here as it is next touched; docs/contributing.md "Adding an effect or a pass".
#ifndef HB_BINDINGS_H
#define HB_BINDINGS_H

#include "shared/gpu_types.h"

#ifdef __cplusplus
namespace hb::gpu {
#endif

// Light culling (frame/passes/light_culling.cpp): tile_frustums, light_view, zbin_sort, zbin_bins
// and light_cull share one set.
HB_CONST uint kCullFrame = 0u;         // uniform FrameConstants
HB_CONST uint kCullLights = 1u;        // GpuLight per scene light
HB_CONST uint kCullFrustums = 2u;      // TileFrustum per tile
HB_CONST uint kCullGrid = 3u;          // LightGridEntry per tile
HB_CONST uint kCullIndices = 4u;       // tile lists or masks (+ z-bins)
HB_CONST uint kCullDepth = 5u;         // the depth, sampled
HB_CONST uint kCullSortedLights = 6u;  // zbin: the lights sorted by view depth
HB_CONST uint kCullOrder = 7u;         // zbin: sorted index -> scene index
HB_CONST uint kCullExtents = 8u;       // zbin: per sorted light its bins [lo, hi]
HB_CONST uint kCullViewLights = 9u;    // GpuViewLight per light
HB_CONST uint kCullViewSpheres = 10u;  // the same, range spheres only
HB_CONST uint kCullBindingCount = 11u;

#ifdef __cplusplus
}  // namespace hb::gpu
#endif

#endif
