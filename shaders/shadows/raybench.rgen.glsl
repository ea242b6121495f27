#version 460
// Ray throughput benchmark, ray-tracing-pipeline backend (see raybench_common.glsl.inc).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_tracing : require
#include "shared/gpu_types.h"
layout(constant_id = 0) const uint LIST_MODE = 0;  // kList*
#include "raybench_common.glsl.inc"

layout(location = 0) rayPayloadEXT uint visible;

bool occluded(vec3 origin, vec3 dir, float tMin, float tMax) {
  visible = 0u;
  traceRayEXT(tlas, gl_RayFlagsTerminateOnFirstHitEXT | gl_RayFlagsOpaqueEXT | gl_RayFlagsSkipClosestHitShaderEXT,
              0xFF, 0, 0, 0, origin, tMin, dir, tMax, 0);
  return visible == 0u;
}

void main() { traceStored(ivec2(gl_LaunchIDEXT.xy)); }
