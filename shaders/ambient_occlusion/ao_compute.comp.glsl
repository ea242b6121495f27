#version 460
// Ambient occlusion by the methods that need no ray tracer (ao_common.glsl.inc): layered depth maps
// (METHOD = kAoLdm) and screen-space HBAO (kAoHbao) and GTAO (kAoGtao).
#extension GL_GOOGLE_include_directive : require
#include "surface_constants.glsl.inc"
layout(constant_id = 2) const uint METHOD = kAoLdm;
layout(local_size_x = 8, local_size_y = 8) in;

#include "ao_common.glsl.inc"

#include "depth_texel.glsl.inc"

float depthAt(ivec2 p) { return fetchDepth(p); }

bool occluded(vec3 origin, vec3 dir, float tMin, float tMax) { return false; }  // not called by ldm, hbao, gtao

void main() { aoPixel(ivec2(gl_GlobalInvocationID.xy)); }
