#version 460
// tests/environment_gpu_test.cpp: the environment's radiance (shaders/environment.glsl.inc) along
// each of a list of directions, to hold the GPU's lookup against the CPU's (scene/environment.cpp).
#extension GL_GOOGLE_include_directive : require
#include "shared/gpu_types.h"
layout(local_size_x = 64) in;

uniform Params { AoConstants ao; };
layout(std430) readonly buffer Directions { vec4 dirs[]; };
layout(std430) writeonly buffer Out { vec4 radiance[]; };

#include "environment.glsl.inc"

layout(push_constant) uniform Push { uint count; } pc;

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  radiance[i] = vec4(envRadiance(dirs[i].xyz), 0.0);
}
