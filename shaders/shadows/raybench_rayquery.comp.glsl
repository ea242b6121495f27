#version 460
// Ray throughput benchmark, ray-query backend (see raybench_common.glsl.inc).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_query : require
#include "shared/gpu_types.h"
layout(constant_id = 0) const uint LIST_MODE = 0;  // kList*
#include "raybench_common.glsl.inc"

layout(local_size_x = 8, local_size_y = 8) in;

#include "rayquery_occluded.glsl.inc"

void main() { traceStored(ivec2(gl_GlobalInvocationID.xy)); }
