#version 460
// Pass 4, ray-tracing-pipeline backend: the same meaning as shadows_rayquery.comp.glsl for devices
// that trace rays but have no ray queries (the NVIDIA H100). One ray-generation invocation per
// pixel; a miss shader marks the light visible; closest-hit shaders are skipped.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_tracing : require
#include "shadows_constants.glsl.inc"

#include "shadows_common.glsl.inc"

#include "depth_texel.glsl.inc"
uniform accelerationStructureEXT tlas;

float depthAt(ivec2 p) { return fetchDepth(p); }

#include "rt_occluded.glsl.inc"

void main() { shadePixel(ivec2(gl_LaunchIDEXT.xy)); }
