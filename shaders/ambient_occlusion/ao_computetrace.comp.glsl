#version 460
// Ambient occlusion by ray tracing through our own BVH (backend=compute, compute_occluded.glsl.inc;
// ao_common.glsl.inc, METHOD = kAoRayTraced or kAoReference): the same rays as ao_rayquery.comp.glsl.
#extension GL_GOOGLE_include_directive : require
#include "surface_constants.glsl.inc"
layout(constant_id = 2) const uint METHOD = kAoRayTraced;
layout(local_size_x = 8, local_size_y = 8) in;

#include "ao_common.glsl.inc"

#include "depth_texel.glsl.inc"
#define HB_BVH_STACK_ID 4  // after ao_common.glsl.inc RADIANCE (3)
#define HB_BVH_THREADS 64u

float depthAt(ivec2 p) { return fetchDepth(p); }

#include "compute_occluded.glsl.inc"

void main() { aoPixel(ivec2(gl_GlobalInvocationID.xy)); }
