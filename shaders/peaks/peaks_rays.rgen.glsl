#version 460
// The device's ray rates through the ray-tracing pipeline (peaks_rays.glsl.inc).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_tracing : require
#include "peaks_rays.glsl.inc"

uniform accelerationStructureEXT tlas;
layout(location = 0) rayPayloadEXT uint missed;  // the miss shader (shadows.rmiss) sets 1

void main() {
  const uvec2 id = gl_LaunchIDEXT.xy, size = gl_LaunchSizeEXT.xy;
  const uint index = id.y * size.x + id.x;
  if (fileMode() && index >= p.file.x) return;  // past the file's last ray
  vec3 origin, dir;
  float tMin, tMax;
  if (!peaksRay(id, size, origin, dir, tMin, tMax)) {
    missedOut[index] = 1u;
    return;
  }
  missed = 0u;
  const uint flags = gl_RayFlagsOpaqueEXT | gl_RayFlagsSkipClosestHitShaderEXT |
                     (anyHitMode() ? gl_RayFlagsTerminateOnFirstHitEXT : 0u);
  traceRayEXT(tlas, flags, 0xFF, 0, 0, 0, origin, tMin, dir, tMax, 0);
  missedOut[index] = missed;
}
