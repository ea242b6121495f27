#version 460
// primary=raycast through ray query (devices that have it: lavapipe); primary_raycast.glsl.inc.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_query : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared/gpu_types.h"

layout(constant_id = 0) const uint ANALYSIS = 0;
layout(local_size_x = 8, local_size_y = 8) in;
#include "primary_raycast.glsl.inc"

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= r3.width || p.y >= r3.height) return;
  if (!cameraHasRay(r3.projection, r3, float(p.x), float(p.y))) {  // paraboloid: outside the disk
    storeHit(p, false, 0.0, 0u);
    return;
  }
  rayQueryEXT rq;
  rayQueryInitializeEXT(rq, tlas, gl_RayFlagsOpaqueEXT, 0xFF, cameraRayOrigin(r3.projection, r3, float(p.x), float(p.y)), r3.depth.x,
                        cameraRayDir(r3.projection, r3, float(p.x), float(p.y)), r3.depth.y);
  while (rayQueryProceedEXT(rq)) {
  }
  const bool hit = rayQueryGetIntersectionTypeEXT(rq, true) == gl_RayQueryCommittedIntersectionTriangleEXT;
  float t = 0.0;
  uint id = 0u;
  if (hit) {
    t = rayQueryGetIntersectionTEXT(rq, true);
    id = triangleId(uint(rayQueryGetIntersectionInstanceCustomIndexEXT(rq, true)),
                    uint(rayQueryGetIntersectionGeometryIndexEXT(rq, true)),
                    uint(rayQueryGetIntersectionPrimitiveIndexEXT(rq, true)));
  }
  storeHit(p, hit, t, id);
}
