#version 460
// The device's ray rates through ray query (peaks_rays.glsl.inc), 8x8 rays a group.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_query : require
layout(local_size_x = 8, local_size_y = 8) in;
#include "peaks_rays.glsl.inc"

layout(binding = HB_PEAKS_TLAS) uniform accelerationStructureEXT tlas;
layout(push_constant) uniform Size { uvec2 size; };

void main() {
  const uvec2 id = gl_GlobalInvocationID.xy;
  if (id.x >= size.x || id.y >= size.y) return;
  const uint index = id.y * size.x + id.x;
  vec3 origin, dir;
  if (!peaksRay(id, size, origin, dir)) {
    missedOut[index] = 1u;
    return;
  }
  rayQueryEXT rq;
  rayQueryInitializeEXT(rq, tlas, gl_RayFlagsOpaqueEXT | (MODE >= 2u ? gl_RayFlagsTerminateOnFirstHitEXT : 0u), 0xFF,
                        origin, 0.0, dir, p.forward.w);
  while (rayQueryProceedEXT(rq)) {
  }
  missedOut[index] = rayQueryGetIntersectionTypeEXT(rq, true) == gl_RayQueryCommittedIntersectionNoneEXT ? 1u : 0u;
}
