#version 460
// Ray throughput benchmark, ray-query backend (see raybench_common.glsl.inc).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_query : require
#include "shared/gpu_types.h"
#include "raybench_common.glsl.inc"

layout(local_size_x = 8, local_size_y = 8) in;

bool occluded(vec3 origin, vec3 dir, float tMin, float tMax) {
  rayQueryEXT rq;
  rayQueryInitializeEXT(rq, tlas, gl_RayFlagsTerminateOnFirstHitEXT | gl_RayFlagsOpaqueEXT, 0xFF, origin,
                        tMin, dir, tMax);
  while (rayQueryProceedEXT(rq)) {
  }
  return rayQueryGetIntersectionTypeEXT(rq, true) != gl_RayQueryCommittedIntersectionNoneEXT;
}

void main() { traceStored(ivec2(gl_GlobalInvocationID.xy)); }
