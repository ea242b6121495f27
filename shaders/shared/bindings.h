// Descriptor bindings (set 0) of the passes, each written once here and used by the pass's shaders
// (layout(binding = HB_...)) and its C++ (the set layout and the descriptor writes). Every pass's
// bindings are here, a block per pass naming its C++ file; a new pass adds its block
// (docs/contributing.md "Adding an effect or a pass"). The one number written elsewhere too is
// HB_INDIRECT_ID_BASE in indirect.rchit.glsl, which includes nothing (it says why).
//
// Macros, not HB_CONST constants: glslang emits every global constant of a shader, used or not,
// so a `const uint` whose value the shader does not otherwise hold adds an OpConstant to its
// SPIR-V; a macro is the number itself. In C++ they are macros too, so they are named as macros
// (HB_<PASS>_<WHAT>): a kName macro would replace any other kName, res::kShadowVisibility say.
#ifndef HB_BINDINGS_H
#define HB_BINDINGS_H

// Light culling (frame/passes/light_culling.cpp): tile_frustums, light_view, zbin_sort, zbin_bins
// and light_cull share one set.
#define HB_CULL_FRAME 0u          // uniform FrameConstants
#define HB_CULL_LIGHTS 1u         // GpuLight per scene light
#define HB_CULL_FRUSTUMS 2u       // TileFrustum per tile
#define HB_CULL_GRID 3u           // LightGridEntry per tile
#define HB_CULL_INDICES 4u        // tile lists or masks (+ z-bins)
#define HB_CULL_DEPTH 5u          // the depth, sampled
#define HB_CULL_SORTED_LIGHTS 6u  // zbin: the lights sorted by view depth
#define HB_CULL_ORDER 7u          // zbin: sorted index -> scene index
#define HB_CULL_EXTENTS 8u        // zbin: per sorted light its bins [lo, hi]
#define HB_CULL_VIEW_LIGHTS 9u    // GpuViewLight per light
#define HB_CULL_VIEW_SPHERES 10u  // the same, range spheres only
#define HB_CULL_BINDING_COUNT 11u

// Shading (frame/passes/shading.cpp): bindings 0-7 are the same in both shading passes
// (shading_bindings.glsl.inc); each pass's own follow from 8, the bindless textures last.
#define HB_SHADE_FRAME 0u          // uniform FrameConstants
#define HB_SHADE_LIGHTS 1u         // GpuLight per scene light
#define HB_SHADE_GRID 2u           // LightGridEntry per tile (USE_GRID)
#define HB_SHADE_INDICES 3u        // the tiles' light lists or masks (USE_GRID)
#define HB_SHADE_VISIBILITY 4u     // the shadow pass's visibility words (SHADOWS)
#define HB_SHADE_MATERIALS 5u      // GpuMaterial per material
#define HB_SHADE_VERTICES 6u       // the scene's vertices, 8 floats each
#define HB_SHADE_SCENE_INDICES 7u  // the scene's triangle indices
// shading.frag.glsl (forward: the scene drawn again against the prepass depth)
#define HB_SHADE_FRAG_VISIBILITY_IDS 8u  // ID_MATCH: (id, t bits) per pixel
#define HB_SHADE_FRAG_AO 9u              // ambient occlusion per pixel (frame.ambient.w = 1)
#define HB_SHADE_FRAG_INDIRECT 10u       // the indirect light image (INDIRECT = 1)
#define HB_SHADE_FRAG_ENVIRONMENT 11u    // the environment light per pixel, vec4 (ENVIRONMENT = 1)
#define HB_SHADE_FRAG_TEXTURES 12u       // bindless sampled textures: the last binding
// shading_visbuffer.comp.glsl (from the visibility buffer, in compute)
#define HB_SHADE_VB_VISIBILITY_IDS 8u   // (id, t bits) per pixel
#define HB_SHADE_VB_RAYS 9u             // uniform Raster3dConstants: the pixels' rays
#define HB_SHADE_VB_DRAWS 10u           // GpuDraw per draw
#define HB_SHADE_VB_TRIANGLE_DRAWS 11u  // draw-order triangle -> its draw
#define HB_SHADE_VB_COLOR 12u           // the colour target, written
#define HB_SHADE_VB_REF_NORMAL 13u      // the reference normal target (analysis), written
#define HB_SHADE_VB_AO 14u              // ambient occlusion per pixel (frame.ambient.w = 1)
#define HB_SHADE_VB_INDIRECT 15u        // the indirect light image (INDIRECT = 1)
#define HB_SHADE_VB_ENVIRONMENT 16u     // the environment light per pixel, vec4 (ENVIRONMENT = 1)
#define HB_SHADE_VB_TEXTURES 17u        // bindless sampled textures: the last binding

// Surfaces: what the shared includes declare (surface.glsl.inc, depth_texel.glsl.inc,
// ldm_trace.glsl.inc) and the ray tracer's `tlas`, at the same numbers in every set that has them:
// the shadow pass (effects/shadows/shadow_pass.cpp), ambient occlusion
// (effects/ambient_occlusion/ao_pass.cpp) and the indirect light with its photon splat
// (effects/indirect/indirect_pass.cpp). Each effect's own bindings fill the numbers between.
#define HB_SURFACE_FRAME 0u           // uniform FrameConstants
#define HB_SURFACE_DEPTH 4u           // the depth, sampled
#define HB_SURFACE_TLAS 5u            // the scene's top-level acceleration structure
#define HB_SURFACE_HIT_IDS 11u        // 3D rasterization's (id, t bits) per pixel (world_pos=hit, normals=geometric)
#define HB_SURFACE_HIT_RAYS 12u       // uniform Raster3dConstants: its rays
#define HB_SURFACE_HIT_TRIANGLES 13u  // its world triangles, 3 vec4 each
#define HB_SURFACE_LDM_MAPS 15u       // the layered depth maps' LdmMap per direction (AO, indirect light)
// backend=compute (compute_occluded.glsl.inc): our BVH instead of HB_SURFACE_TLAS.
#define HB_SURFACE_BVH_NODES 22u      // gpu::PrimaryBvhNode
#define HB_SURFACE_BVH_TRIANGLES 23u  // 3 vec4 per triangle, in leaf order

// Shadows (effects/shadows/shadow_pass.cpp): shadows_common.glsl.inc, with the HB_SURFACE_* bindings.
#define HB_SHADOW_LIGHTS 1u      // GpuLight per scene light
#define HB_SHADOW_GRID 2u        // LightGridEntry per tile
#define HB_SHADOW_INDICES 3u     // the tiles' light lists or masks
#define HB_SHADOW_VISIBILITY 6u  // the visibility words, written (shading reads them at HB_SHADE_VISIBILITY)
#define HB_SHADOW_ACCOUNTING 7u  // analysis: the per-pixel ray accounting image
#define HB_SHADOW_NORMALS 8u     // analysis: the normal image
#define HB_SHADOW_POSITIONS 9u   // analysis: the world positions (raybench reads them at HB_RAYBENCH_POSITIONS)
#define HB_SHADOW_TRACED 10u     // analysis: as visibility, bit = ray traced (raybench: HB_RAYBENCH_TRACED)

// Ray throughput benchmark (effects/shadows/raybench_pass.cpp): raybench_common.glsl.inc, its own set.
#define HB_RAYBENCH_FRAME 0u           // uniform FrameConstants
#define HB_RAYBENCH_LIGHTS 1u          // GpuLight per scene light
#define HB_RAYBENCH_GRID 2u            // LightGridEntry per tile
#define HB_RAYBENCH_INDICES 3u         // the tiles' light lists or masks
#define HB_RAYBENCH_POSITIONS 4u       // the shadow pass's world positions (HB_SHADOW_POSITIONS)
#define HB_RAYBENCH_TRACED 5u          // the shadow pass's traced-ray words (HB_SHADOW_TRACED)
#define HB_RAYBENCH_TLAS 6u            // the scene's top-level acceleration structure
#define HB_RAYBENCH_RESULT 7u          // written, keeps the rays alive
#define HB_RAYBENCH_VISIBILITY 8u      // the shadow pass's visibility (zbin: the pixels' bin ranges)
#define HB_RAYBENCH_BVH_NODES 9u       // backend=compute: HB_SURFACE_BVH_NODES
#define HB_RAYBENCH_BVH_TRIANGLES 10u  // backend=compute: HB_SURFACE_BVH_TRIANGLES

// Ambient occlusion (effects/ambient_occlusion/ao_pass.cpp): ao_common.glsl.inc, with the HB_SURFACE_*
// bindings (HB_SURFACE_TLAS only where the frame has a ray tracer).
#define HB_AO_DIRECTIONS 14u   // the N directions, vec4 each
#define HB_AO_OUT 17u          // AO per pixel, written
#define HB_AO_PARAMS 18u       // uniform AoConstants
#define HB_AO_ENVIRONMENT 19u  // environment light (RADIANCE = 1): the equirectangular map, vec4 per texel

// Indirect light and its photon splat (effects/indirect/indirect_pass.cpp): indirect_common.glsl.inc,
// indirect.rchit.glsl and photon_splat.*.glsl share one set, with the HB_SURFACE_* bindings.
#define HB_INDIRECT_LIGHTS 1u           // GpuLight per scene light
#define HB_INDIRECT_VERTICES 6u         // the scene's vertices, 8 floats each
#define HB_INDIRECT_SCENE_INDICES 7u    // the scene's triangle indices
#define HB_INDIRECT_MATERIALS 8u        // GpuMaterial per material
#define HB_INDIRECT_DRAWS 9u            // GpuDraw per draw
#define HB_INDIRECT_TRIANGLE_DRAWS 10u  // draw-order triangle -> its draw
#define HB_INDIRECT_DIRECTIONS 14u      // the N split directions, vec4 each
#define HB_INDIRECT_ID_BASE 16u         // instance/geometry -> first draw-order triangle id
#define HB_INDIRECT_PHOTONS 17u         // Photon per slot: written by the trace, read by the splat
#define HB_INDIRECT_PARAMS 18u          // uniform IndirectConstants
#define HB_INDIRECT_FACES 19u           // PhotonFace per emitting image plane
#define HB_INDIRECT_IRRADIANCE 20u      // the irradiance image (reference), written
#define HB_INDIRECT_TEXTURES 24u        // bindless sampled textures: the last binding (after HB_SURFACE_BVH_*)
// The compute splat's own buffers (splat=compute: photon_splat_bin.comp.glsl, photon_splat.comp.glsl),
// in set 1 beside the indirect set.
#define HB_SPLAT_BOXES 0u   // uvec2 per slot: its footprint's pixel box (x0 | y0 << 16, x1 | y1 << 16)
#define HB_SPLAT_COARSE 1u  // uint per slot: the same box in coarse bins (x0 | y0 << 8 | x1 << 16 | y1 << 24)
#define HB_SPLAT_COUNTS 2u  // uint per (bin, chunk): slots of the chunk that overlap the bin, then their start
#define HB_SPLAT_BINS 3u    // uvec4 per bin: its list's start, count, whether it fit the list's capacity
#define HB_SPLAT_LIST 4u    // uint: each bin's overlapping slots, in slot order, bin after bin

// Layered depth maps' build (frame/passes/ldm_build.cpp): the build's set (ldm_build.vert/frag for
// the hardware build, ldm_build_3dr.comp) and the sbuffer list's scan set (ldm_sbuffer.comp: 1-3).
#define HB_LDM_MAPS 0u           // LdmMap per map (hardware: vertex stage)
#define HB_LDM_LINKS_ADDRESS 1u  // uniform: the links buffer's device address (lo, hi)
#define HB_LDM_COUNTERS 2u       // the node pool's and the lists' counters
#define HB_LDM_TRIANGLES 3u      // ldm_build=3dr: the world triangles, 3 vec4 each
#define HB_LDM_BLOCK_SUMS 3u     // the scan set: per block of 4096 counts its sum
#define HB_LDM_CHUNKS 4u         // ldm_build=3dr: the large pairs' 64-pixel chunks (gpu_types.h kLdmCounterChunks)

// 3D rasterization (frame/passes/raster3d.cpp): raster3d_common.glsl.inc (raster3d.comp,
// raster3d_tiles.comp, raster3d_scan.comp) share one set; raster3d_resolve.comp has its own.
#define HB_R3D_CONSTANTS 0u   // uniform Raster3dConstants
#define HB_R3D_TRIANGLES 1u   // the world triangles, 3 vec4 each
#define HB_R3D_VISIBILITY 2u  // (t bits << 32 | id) per pixel
#define HB_R3D_ITEMS 3u       // the work items' count and list
#define HB_R3D_COUNTERS 4u    // analysis counters (kR3dCounterCount)
#define HB_R3D_COVERAGE 5u    // analysis: covering triangles per pixel
#define HB_R3D_TESTED 6u      // analysis: pixel tests per pixel
#define HB_R3D_BINS 7u        // 3dr-binned: per screen tile count, first entry, fill cursor
#define HB_R3D_BIN_LIST 8u    // 3dr-binned: the tiles' lists
#define HB_R3D_BVH_NODES 9u   // BVH methods: gpu::PrimaryBvhNode, the root first
#define HB_R3D_BVH_ORDER 10u  // BVH methods: triangle ids in leaf order
#define HB_R3D_BINDING_COUNT 11u
#define HB_R3D_RESOLVE_CONSTANTS 0u   // raster3d_resolve.comp: uniform Raster3dConstants
#define HB_R3D_RESOLVE_VISIBILITY 1u  // the visibility buffer, read
#define HB_R3D_RESOLVE_DEPTH 2u       // the depth per pixel, written (copied into the depth image)
#define HB_R3D_RESOLVE_BINDING_COUNT 3u

// Primary visibility by ray casting (frame/passes/raster3d.cpp): primary_raycast.glsl.inc
// (primary_raycast.comp, .rgen, .rchit) share one set; then raster3d_resolve.comp as above.
#define HB_CAST_CONSTANTS 0u   // uniform Raster3dConstants
#define HB_CAST_VISIBILITY 1u  // (t bits << 32 | id) per pixel, written
#define HB_CAST_ID_BASE 2u     // instance/geometry -> first draw-order triangle id
#define HB_CAST_TLAS 3u        // the scene's top-level acceleration structure
#define HB_CAST_COUNTERS 4u    // analysis counters (kR3dCounterCount)
#define HB_CAST_COVERAGE 5u    // analysis: 1 where the pixel's ray hit
#define HB_CAST_BINDING_COUNT 6u
#define HB_CAST_BVH_NODES 6u      // backend=compute: our BVH instead of HB_CAST_TLAS (gpu::PrimaryBvhNode)
#define HB_CAST_BVH_TRIANGLES 7u  // backend=compute: 3 vec4 per triangle, in leaf order

// The device's own ceilings (gpu/peaks.cpp): peaks/peaks.comp and peaks/peaks_atomic64.comp.
#define HB_PEAKS_SRC 0u            // the buffer read (read, copy)
#define HB_PEAKS_DST 1u            // the buffer written (write, copy, atomics, the sink of read and FMA)
#define HB_PEAKS_TLAS 2u           // peaks_rays.rgen: the scene's top-level acceleration structure
#define HB_PEAKS_PARAMS 3u         // peaks_rays.rgen: uniform camera and bounds
#define HB_PEAKS_HITS 4u           // peaks_rays: the camera rays' t (MODE 3's origins)
#define HB_PEAKS_BVH_NODES 5u      // peaks_rays_compute: our BVH (gpu::PrimaryBvhNode)
#define HB_PEAKS_BVH_TRIANGLES 6u  // peaks_rays_compute: 3 vec4 per triangle, in leaf order
#define HB_PEAKS_NEXT_RAY 7u       // peaks_rays_compute, persistent threads: the next ray to take
#define HB_PEAKS_BINDING_COUNT 4u  // peaks.comp's

#endif
