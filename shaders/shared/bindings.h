// Descriptor bindings (set 0) of the passes, each written once here and used by the pass's shaders
// (layout(binding = k...)) and its C++ (the set layout and the descriptor writes). A pass moves
// its bindings here as it is next touched; docs/contributing.md "Adding an effect or a pass".
//
// Macros, not HB_CONST constants: glslang emits every global constant of a shader, used or not,
// so a `const uint` whose value the shader does not otherwise hold adds an OpConstant to its
// SPIR-V; a macro is the number itself. In C++ they are macros too (no gpu:: before them).
#ifndef HB_BINDINGS_H
#define HB_BINDINGS_H

// Light culling (frame/passes/light_culling.cpp): tile_frustums, light_view, zbin_sort, zbin_bins
// and light_cull share one set.
#define kCullFrame 0u         // uniform FrameConstants
#define kCullLights 1u        // GpuLight per scene light
#define kCullFrustums 2u      // TileFrustum per tile
#define kCullGrid 3u          // LightGridEntry per tile
#define kCullIndices 4u       // tile lists or masks (+ z-bins)
#define kCullDepth 5u         // the depth, sampled
#define kCullSortedLights 6u  // zbin: the lights sorted by view depth
#define kCullOrder 7u         // zbin: sorted index -> scene index
#define kCullExtents 8u       // zbin: per sorted light its bins [lo, hi]
#define kCullViewLights 9u    // GpuViewLight per light
#define kCullViewSpheres 10u  // the same, range spheres only
#define kCullBindingCount 11u

#endif
