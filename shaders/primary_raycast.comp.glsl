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

#include "rayquery_closest.glsl.inc"

bool castClosest(vec3 origin, vec3 dir, float tMin, float tMax, out float t, out uint id) { return rayQueryClosestHit(origin, dir, tMin, tMax, t, id); }
