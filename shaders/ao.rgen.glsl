#version 460
// Ambient occlusion by ray tracing through the ray-tracing pipeline (ao_common.glsl.inc, METHOD =
// kAoRayTraced or kAoReference), for devices without ray queries (the NVIDIA H100); the miss
// shader is the shadow pass's (shadows.rmiss.glsl: payload 1 = nothing hit).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_tracing : require
#include "shared/gpu_types.h"

layout(constant_id = 0) const uint NORMALS = 0;
layout(constant_id = 1) const uint WORLD_POS = 0;
layout(constant_id = 2) const uint METHOD = kAoRayTraced;

#include "ao_common.glsl.inc"

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

void main() { aoPixel(ivec2(gl_LaunchIDEXT.xy)); }
