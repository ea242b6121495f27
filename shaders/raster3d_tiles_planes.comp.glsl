#version 460
// 3dr-binned's tile pass with shared sample planes (raster3d_common.glsl.inc): the centre and every
// stored sample of anti-aliasing in one pass over the tile's list, in timed frames of a perspective
// view without early-z (Raster3dPass::sharedPlanes). The body is raster3d_tiles.comp.glsl's
// (raster3d_tiles.glsl.inc); plane by plane it is that shader, which has none of this code.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_control_flow_attributes : require
#include "shared/gpu_types.h"

#define R3D_SAMPLE_PLANES
#include "raster3d_common.glsl.inc"
#include "raster3d_tiles.glsl.inc"
