#version 460
// Ray throughput benchmark, compute backend (our BVH: compute_occluded.glsl.inc; see
// raybench_common.glsl.inc).
#extension GL_GOOGLE_include_directive : require
#include "shared/gpu_types.h"
#define HB_RAYBENCH_COMPUTE 1
layout(constant_id = 0) const uint LIST_MODE = 0;  // kList*
#include "raybench_common.glsl.inc"

layout(local_size_x = 8, local_size_y = 8) in;

#define HB_BVH_STACK_ID 1
#define HB_BVH_THREADS 64u
#include "compute_occluded.glsl.inc"

void main() { traceStored(ivec2(gl_GlobalInvocationID.xy)); }
