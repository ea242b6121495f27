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

// Shading (frame/passes/shading.cpp): bindings 0-7 are the same in both shading passes
// (shading_bindings.glsl.inc); each pass's own follow from 8, the bindless textures last.
#define kShadeFrame 0u         // uniform FrameConstants
#define kShadeLights 1u        // GpuLight per scene light
#define kShadeGrid 2u          // LightGridEntry per tile (USE_GRID)
#define kShadeIndices 3u       // the tiles' light lists or masks (USE_GRID)
#define kShadeVisibility 4u    // the shadow pass's visibility words (SHADOWS)
#define kShadeMaterials 5u     // GpuMaterial per material
#define kShadeVertices 6u      // the scene's vertices, 8 floats each
#define kShadeSceneIndices 7u  // the scene's triangle indices
// shading.frag.glsl (forward: the scene drawn again against the prepass depth)
#define kShadeFragVisibilityIds 8u  // ID_MATCH: (id, t bits) per pixel
#define kShadeFragAo 9u             // ambient occlusion per pixel (frame.ambient.w = 1)
#define kShadeFragIndirect 10u      // the indirect light image (INDIRECT = 1)
#define kShadeFragTextures 11u      // bindless sampled textures: the last binding
// shading_visbuffer.comp.glsl (from the visibility buffer, in compute)
#define kShadeVbVisibilityIds 8u   // (id, t bits) per pixel
#define kShadeVbRays 9u            // uniform Raster3dConstants: the pixels' rays
#define kShadeVbDraws 10u          // GpuDraw per draw
#define kShadeVbTriangleDraws 11u  // draw-order triangle -> its draw
#define kShadeVbColor 12u          // the colour target, written
#define kShadeVbRefNormal 13u      // the reference normal target (analysis), written
#define kShadeVbAo 14u             // ambient occlusion per pixel (frame.ambient.w = 1)
#define kShadeVbIndirect 15u       // the indirect light image (INDIRECT = 1)
#define kShadeVbTextures 16u       // bindless sampled textures: the last binding

// Surfaces: what the shared includes declare (surface.glsl.inc, depth_texel.glsl.inc,
// ldm_trace.glsl.inc) and the ray tracer's `tlas`, at the same numbers in every set that has them:
// the shadow pass (effects/shadows/shadow_pass.cpp), ambient occlusion
// (effects/ambient_occlusion/ao_pass.cpp) and the indirect light with its photon splat
// (effects/indirect/indirect_pass.cpp). Each effect's own bindings fill the numbers between.
#define kSurfaceFrame 0u          // uniform FrameConstants
#define kSurfaceDepth 4u          // the depth, sampled
#define kSurfaceTlas 5u           // the scene's top-level acceleration structure
#define kSurfaceHitIds 11u        // 3D rasterization's (id, t bits) per pixel (world_pos=hit, normals=geometric)
#define kSurfaceHitRays 12u       // uniform Raster3dConstants: its rays
#define kSurfaceHitTriangles 13u  // its world triangles, 3 vec4 each
#define kSurfaceLdmMaps 15u       // the layered depth maps' LdmMap per direction (AO, indirect light)

// Shadows (effects/shadows/shadow_pass.cpp): shadows_common.glsl.inc, with the kSurface* bindings.
#define kShadowLights 1u      // GpuLight per scene light
#define kShadowGrid 2u        // LightGridEntry per tile
#define kShadowIndices 3u     // the tiles' light lists or masks
#define kShadowVisibility 6u  // the visibility words, written (shading reads them at kShadeVisibility)
#define kShadowAccounting 7u  // analysis: the per-pixel ray accounting image
#define kShadowNormals 8u     // analysis: the normal image
#define kShadowPositions 9u   // analysis: the world positions (raybench reads them at kRaybenchPositions)
#define kShadowTraced 10u     // analysis: as visibility, bit = ray traced (raybench: kRaybenchTraced)

// Ray throughput benchmark (effects/shadows/raybench_pass.cpp): raybench_common.glsl.inc, its own set.
#define kRaybenchFrame 0u       // uniform FrameConstants
#define kRaybenchLights 1u      // GpuLight per scene light
#define kRaybenchGrid 2u        // LightGridEntry per tile
#define kRaybenchIndices 3u     // the tiles' light lists or masks
#define kRaybenchPositions 4u   // the shadow pass's world positions (kShadowPositions)
#define kRaybenchTraced 5u      // the shadow pass's traced-ray words (kShadowTraced)
#define kRaybenchTlas 6u        // the scene's top-level acceleration structure
#define kRaybenchResult 7u      // written, keeps the rays alive
#define kRaybenchVisibility 8u  // the shadow pass's visibility (zbin: the pixels' bin ranges)

// Ambient occlusion (effects/ambient_occlusion/ao_pass.cpp): ao_common.glsl.inc, with the kSurface*
// bindings (kSurfaceTlas only where the frame has a ray tracer).
#define kAoDirections 14u  // the N directions, vec4 each
#define kAoOut 17u         // AO per pixel, written
#define kAoParams 18u      // uniform AoConstants

// Indirect light and its photon splat (effects/indirect/indirect_pass.cpp): indirect_common.glsl.inc,
// indirect.rchit.glsl and photon_splat.*.glsl share one set, with the kSurface* bindings.
#define kIndirectLights 1u          // GpuLight per scene light
#define kIndirectVertices 6u        // the scene's vertices, 8 floats each
#define kIndirectSceneIndices 7u    // the scene's triangle indices
#define kIndirectMaterials 8u       // GpuMaterial per material
#define kIndirectDraws 9u           // GpuDraw per draw
#define kIndirectTriangleDraws 10u  // draw-order triangle -> its draw
#define kIndirectDirections 14u     // the N split directions, vec4 each
#define kIndirectIdBase 16u         // instance/geometry -> first draw-order triangle id
#define kIndirectPhotons 17u        // Photon per slot: written by the trace, read by the splat
#define kIndirectParams 18u         // uniform IndirectConstants
#define kIndirectFaces 19u          // PhotonFace per emitting image plane
#define kIndirectIrradiance 20u     // the irradiance image (reference), written
#define kIndirectTextures 21u       // bindless sampled textures: the last binding

// Layered depth maps' build (frame/passes/ldm_build.cpp): the build's set (ldm_build.vert/frag for
// the hardware build, ldm_build_3dr.comp) and the sbuffer list's scan set (ldm_sbuffer.comp: 1-3).
#define kLdmMaps 0u          // LdmMap per map (hardware: vertex stage)
#define kLdmLinksAddress 1u  // uniform: the links buffer's device address (lo, hi)
#define kLdmCounters 2u      // the node pool's and the lists' counters
#define kLdmTriangles 3u     // ldm_build=3dr: the world triangles, 3 vec4 each
#define kLdmBlockSums 3u     // the scan set: per block of 4096 counts its sum

// 3D rasterization (frame/passes/raster3d.cpp): raster3d_common.glsl.inc (raster3d.comp,
// raster3d_tiles.comp, raster3d_scan.comp) share one set; raster3d_resolve.comp has its own.
#define kR3dConstants 0u   // uniform Raster3dConstants
#define kR3dTriangles 1u   // the world triangles, 3 vec4 each
#define kR3dVisibility 2u  // (t bits << 32 | id) per pixel
#define kR3dItems 3u       // the work items' count and list
#define kR3dCounters 4u    // analysis counters (kR3dCounterCount)
#define kR3dCoverage 5u    // analysis: covering triangles per pixel
#define kR3dTested 6u      // analysis: pixel tests per pixel
#define kR3dBins 7u        // 3dr-binned: per screen tile count, first entry, fill cursor
#define kR3dBinList 8u     // 3dr-binned: the tiles' lists
#define kR3dBindingCount 9u
#define kR3dResolveConstants 0u   // raster3d_resolve.comp: uniform Raster3dConstants
#define kR3dResolveVisibility 1u  // the visibility buffer, read
#define kR3dResolveDepth 2u       // the depth per pixel, written (copied into the depth image)
#define kR3dResolveBindingCount 3u

// Primary visibility by ray casting (frame/passes/raster3d.cpp): primary_raycast.glsl.inc
// (primary_raycast.comp, .rgen, .rchit) share one set; then raster3d_resolve.comp as above.
#define kCastConstants 0u   // uniform Raster3dConstants
#define kCastVisibility 1u  // (t bits << 32 | id) per pixel, written
#define kCastIdBase 2u      // instance/geometry -> first draw-order triangle id
#define kCastTlas 3u        // the scene's top-level acceleration structure
#define kCastCounters 4u    // analysis counters (kR3dCounterCount)
#define kCastCoverage 5u    // analysis: 1 where the pixel's ray hit
#define kCastBindingCount 6u

#endif
