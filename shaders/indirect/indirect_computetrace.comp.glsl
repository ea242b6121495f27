#version 460
// Indirect light through our own BVH (backend=compute, compute_occluded.glsl.inc;
// indirect_common.glsl.inc): the same photons and gather rays as indirect.comp.glsl, with
// closestHitBvh for photons and gather rays and occluded() for the reference's light rays.
#extension GL_GOOGLE_include_directive : require
#include "surface_constants.glsl.inc"
layout(constant_id = 2) const uint METHOD = kIndirectLdm;
layout(local_size_x = 64) in;

#define HB_INDIRECT_COMPUTE_MAIN  // main: indirect_common.glsl.inc
#include "indirect_common.glsl.inc"

#include "depth_texel.glsl.inc"
#define HB_BVH_STACK_ID 4  // after indirect_common.glsl.inc BOUNCE (3)
#define HB_BVH_THREADS 64u
#define HB_BVH_CLOSEST  // closest hits: the stack keeps entry distances

float depthAt(ivec2 p) { return fetchDepth(p); }

#include "compute_occluded.glsl.inc"

bool closestHit(vec3 origin, vec3 dir, float tMin, float tMax, out float t, out uint id) {
  return closestHitBvh(origin, dir, tMin, tMax, t, id);
}
