#version 460
// Pass 4, ray-tracing-pipeline backend: the same meaning as shadows_rayquery.comp.glsl for devices
// that trace rays but have no ray queries (the NVIDIA H100). One ray-generation invocation per
// pixel; a miss shader marks the light visible; closest-hit shaders are skipped.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_tracing : require
#include "shared/gpu_types.h"

layout(constant_id = 0) const uint TILE = 16;
layout(constant_id = 1) const uint NORMALS = 0;
layout(constant_id = 2) const uint WORLD_POS = 0;
layout(constant_id = 3) const uint RANGE_TEST = 0;
layout(constant_id = 4) const uint ANALYSIS = 0;

#include "shadows_common.glsl.inc"

layout(set = 0, binding = 4) uniform sampler2D depthTex;
layout(set = 0, binding = 5) uniform accelerationStructureEXT tlas;
layout(location = 0) rayPayloadEXT uint visible;

float depthAt(ivec2 p) {
  if (p.x < 0 || p.y < 0 || p.x >= int(frame.extent.x) || p.y >= int(frame.extent.y)) return 0.0;
  return texelFetch(depthTex, p, 0).r;
}

bool occluded(vec3 origin, vec3 dir, float tMin, float tMax) {
  visible = 0u;
  traceRayEXT(tlas, gl_RayFlagsTerminateOnFirstHitEXT | gl_RayFlagsOpaqueEXT | gl_RayFlagsSkipClosestHitShaderEXT,
              0xFF, 0, 0, 0, origin, tMin, dir, tMax, 0);
  return visible == 0u;
}

void main() { shadePixel(ivec2(gl_LaunchIDEXT.xy)); }
