#version 460
// 3dr-binned, last: one workgroup per screen 8x8 tile, a pixel per thread. The tile's triangles
// (the list the count-scan-fill passes built; PASS 0 made their setups) are read 64 at a time into
// shared memory; each thread keeps its pixel's nearest key in a register and does one atomicMin at
// the end (against the small triangles PASS 0 rasterized directly). Shared memory lives only in
// this shader (and the scan's), so the per-triangle and per-item passes keep full occupancy.
// EARLYZ (2dr-binned always, 3dr-binned with r3d_early_z): each thread starts from its pixel's key
// so far (the small triangles of PASS 0), and before each batch the tile's farthest depth so far is
// reduced in shared memory; a triangle whose nearest vertex depth (less a rounding margin) is
// farther than it gives every pixel a larger t, hence a larger key whatever its id, and is skipped
// (counted as blocks_culled_early_z). The result is the same bit for bit.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared/gpu_types.h"

#include "raster3d_common.glsl.inc"
#include "raster3d_tiles.glsl.inc"
