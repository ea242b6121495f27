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
#include "primary_raycast.glsl.inc"

#define HB_BVH_NODES_BINDING HB_CAST_BVH_NODES
#define HB_BVH_TRIANGLES_BINDING HB_CAST_BVH_TRIANGLES
#define HB_BVH_STACK_ID 1
#define HB_BVH_THREADS 64u
#define HB_BVH_CLOSEST  // closest hits: the stack keeps entry distances
#include "compute_occluded.glsl.inc"

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= r3.width || p.y >= r3.height) return;
  if (!cameraHasRay(r3.projection, r3, float(p.x), float(p.y))) {  // paraboloid: outside the disk
    storeHit(p, false, 0.0, 0u);
    return;
  }
  float t;
  uint id;
  const bool hit = closestHitBvh(cameraRayOrigin(r3.projection, r3, float(p.x), float(p.y)),
                                 cameraRayDir(r3.projection, r3, float(p.x), float(p.y)), r3.depth.x, r3.depth.y, t, id);
  storeHit(p, hit, t, id);
}
