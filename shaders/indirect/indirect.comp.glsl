#version 460
// Indirect light through ray queries (indirect_common.glsl.inc): photon tracing (METHOD = ldm or
// raytraced, a group of 64 threads per primary photon) or the gathered reference (one thread per
// pixel), 64 threads a group over a 2D grid of groups (group = y·groupsX + x).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_query : require
#include "surface_constants.glsl.inc"
layout(constant_id = 2) const uint METHOD = kIndirectLdm;
layout(local_size_x = 64) in;

#define HB_INDIRECT_COMPUTE_MAIN  // main: indirect_common.glsl.inc
#include "indirect_common.glsl.inc"

#include "depth_texel.glsl.inc"
uniform accelerationStructureEXT tlas;

float depthAt(ivec2 p) { return fetchDepth(p); }

#include "rayquery_occluded.glsl.inc"

#include "rayquery_closest.glsl.inc"

bool closestHit(vec3 origin, vec3 dir, float tMin, float tMax, out float t, out uint id) { return rayQueryClosestHit(origin, dir, tMin, tMax, t, id); }
