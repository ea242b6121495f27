#version 460
// The device's ray rates through our own BVH (backend=compute; peaks_rays.glsl.inc,
// compute_occluded.glsl.inc), 8x8 rays a group, or persistent threads (PERSISTENT = 1). MODE 0 also
// writes each camera ray's t for MODE 3, and MODE 4 each file ray's t and triangle.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_ballot : require
layout(local_size_x = 8, local_size_y = 8) in;
#include "shared/gpu_types.h"
#define HB_PEAKS_COMPUTE_MAIN
#define HB_PEAKS_PERSISTENT 4  // the specialization constant's id, after the BVH's three
#include "peaks_rays.glsl.inc"

#define HB_BVH_STACK_ID 1
#define HB_BVH_THREADS 64u
#define HB_BVH_CLOSEST  // closest hits: the stack keeps entry distances
#include "compute_occluded.glsl.inc"

// MODE 4: the triangle each file ray meets (its draw-order id; 0xFFFFFFFF: missed), for raybench's
// --hits-out and its comparison of triangles.
layout(std430) buffer HitIds { uint hitIdOut[]; };

bool peaksHit(vec3 origin, vec3 dir, float tMin, float tMax, uint index) {
  if (anyHitMode()) return occluded(origin, dir, tMin, tMax);
  float t;
  uint tri;
  const bool hit = closestHitBvh(origin, dir, tMin, tMax, t, tri);
  if (MODE == 0u || MODE == 4u) cameraHitT[index] = hit ? t : -1.0;
  if (MODE == 4u) hitIdOut[index] = hit ? tri : 0xFFFFFFFFu;
  return hit;
}
