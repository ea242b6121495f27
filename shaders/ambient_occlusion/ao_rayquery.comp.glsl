#version 460
// Ambient occlusion by ray tracing through ray query (ao_common.glsl.inc, METHOD = kAoRayTraced
// or kAoReference): the same rays as ao.rgen.glsl on devices with VK_KHR_ray_query.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_query : require
#include "surface_constants.glsl.inc"
layout(constant_id = 2) const uint METHOD = kAoRayTraced;
layout(local_size_x = 8, local_size_y = 8) in;

#include "ao_common.glsl.inc"

#include "depth_texel.glsl.inc"
uniform accelerationStructureEXT tlas;

float depthAt(ivec2 p) { return fetchDepth(p); }

#include "rayquery_occluded.glsl.inc"

void main() { aoPixel(ivec2(gl_GlobalInvocationID.xy)); }
