#version 460
// primary=raycast through ray query (devices that have it: lavapipe); primary_raycast.glsl.inc.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_query : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared/gpu_types.h"

layout(constant_id = 0) const uint ANALYSIS = 0;
layout(local_size_x = 8, local_size_y = 8) in;
#define HB_CAST_COMPUTE_MAIN
#include "primary_raycast.glsl.inc"

bool castClosest(vec3 origin, vec3 dir, float tMin, float tMax, out float t, out uint id) {
  rayQueryEXT rq;
  rayQueryInitializeEXT(rq, tlas, gl_RayFlagsOpaqueEXT, 0xFF, origin, tMin, dir, tMax);
  while (rayQueryProceedEXT(rq)) {
  }
  t = 0.0;
  id = 0u;
  if (rayQueryGetIntersectionTypeEXT(rq, true) != gl_RayQueryCommittedIntersectionTriangleEXT) return false;
  t = rayQueryGetIntersectionTEXT(rq, true);
  id = triangleId(uint(rayQueryGetIntersectionInstanceCustomIndexEXT(rq, true)),
                  uint(rayQueryGetIntersectionGeometryIndexEXT(rq, true)),
                  uint(rayQueryGetIntersectionPrimitiveIndexEXT(rq, true)));
  return true;
}
