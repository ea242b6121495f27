#version 460
// Indirect light through the ray-tracing pipeline (devices without ray queries: the H100/H200),
// indirect_common.glsl.inc: launched over (width, height) pixels for the gathered reference, or
// over (kPhotonLanes, primaries) for the photons (primary photon y, lane x). Closest hits come from
// indirect.rchit.glsl as (t bits, triangle id); the miss shader sets the id to ~0.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_tracing : require
#include "surface_constants.glsl.inc"
layout(constant_id = 2) const uint METHOD = kIndirectLdm;

#include "indirect_common.glsl.inc"

#include "depth_texel.glsl.inc"
uniform accelerationStructureEXT tlas;
layout(location = 0) rayPayloadEXT uvec2 hitTId;  // (t bits, id); id ~0: nothing hit

float depthAt(ivec2 p) { return fetchDepth(p); }

bool closestHit(vec3 origin, vec3 dir, float tMin, float tMax, out float t, out uint id) {
  hitTId = uvec2(0u, 0xFFFFFFFFu);
  traceRayEXT(tlas, gl_RayFlagsOpaqueEXT, 0xFF, 0, 0, 0, origin, tMin, dir, tMax, 0);
  t = uintBitsToFloat(hitTId.x);
  id = hitTId.y;
  return id != 0xFFFFFFFFu;
}

bool occluded(vec3 origin, vec3 dir, float tMin, float tMax) {
  hitTId = uvec2(0u, 0u);  // stays unless the miss shader runs
  traceRayEXT(tlas, gl_RayFlagsTerminateOnFirstHitEXT | gl_RayFlagsOpaqueEXT | gl_RayFlagsSkipClosestHitShaderEXT,
              0xFF, 0, 0, 0, origin, tMin, dir, tMax, 0);
  return hitTId.y != 0xFFFFFFFFu;
}

void main() {
  if (METHOD == kIndirectReference)
    gatherPixel(ivec2(gl_LaunchIDEXT.xy));
  else if (BOUNCE >= 2u)
    bounceTrace(gl_LaunchIDEXT.y * 64u + gl_LaunchIDEXT.x);  // a launch of (64, slots / 64)
  else
    photonTrace(gl_LaunchIDEXT.y, gl_LaunchIDEXT.x);
}
