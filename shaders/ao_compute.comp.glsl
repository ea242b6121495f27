#version 460
// Ambient occlusion by the methods that need no ray tracer (ao_common.glsl.inc): layered depth maps
// (METHOD = kAoLdm) and screen-space HBAO (kAoHbao).
#extension GL_GOOGLE_include_directive : require
#include "shared/gpu_types.h"

layout(constant_id = 0) const uint NORMALS = 0;
layout(constant_id = 1) const uint WORLD_POS = 0;
layout(constant_id = 2) const uint METHOD = kAoLdm;
layout(local_size_x = 8, local_size_y = 8) in;

#include "ao_common.glsl.inc"

layout(set = 0, binding = 4) uniform sampler2D depthTex;

float depthAt(ivec2 p) {
  if (p.x < 0 || p.y < 0 || p.x >= int(frame.extent.x) || p.y >= int(frame.extent.y)) return 0.0;
  return texelFetch(depthTex, p, 0).r;
}

bool occluded(vec3 origin, vec3 dir, float tMin, float tMax) { return false; }  // not called by ldm, hbao

void main() { aoPixel(ivec2(gl_GlobalInvocationID.xy)); }
