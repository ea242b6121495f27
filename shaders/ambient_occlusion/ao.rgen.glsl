#version 460
// Ambient occlusion by ray tracing through the ray-tracing pipeline (ao_common.glsl.inc, METHOD =
// kAoRayTraced or kAoReference), for devices without ray queries (the NVIDIA H100); the miss
// shader is the shadow pass's (shadows.rmiss.glsl: payload 1 = nothing hit).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_tracing : require
#include "surface_constants.glsl.inc"
layout(constant_id = 2) const uint METHOD = kAoRayTraced;

#include "ao_common.glsl.inc"

#include "depth_texel.glsl.inc"
uniform accelerationStructureEXT tlas;

float depthAt(ivec2 p) { return fetchDepth(p); }

#include "rt_occluded.glsl.inc"

void main() { aoPixel(ivec2(gl_LaunchIDEXT.xy)); }
