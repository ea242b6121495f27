#version 460
// primary=raycast through our own BVH (backend=compute, compute_occluded.glsl.inc closestHitBvh):
// the same camera rays as primary_raycast.comp.glsl, the nearest hit's t and draw-order id.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared/gpu_types.h"

layout(constant_id = 0) const uint ANALYSIS = 0;
layout(local_size_x = 8, local_size_y = 8) in;
#define HB_CAST_COMPUTE
#define HB_CAST_COMPUTE_MAIN
#include "primary_raycast.glsl.inc"

#define HB_BVH_STACK_ID 1
#define HB_BVH_THREADS 64u
#define HB_BVH_CLOSEST  // closest hits: the stack keeps entry distances
#include "compute_occluded.glsl.inc"

bool castClosest(vec3 origin, vec3 dir, float tMin, float tMax, out float t, out uint id) {
  return closestHitBvh(origin, dir, tMin, tMax, t, id);
}
