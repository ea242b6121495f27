#version 460
// The device's 64-bit atomicMin rate (gpu/peaks.cpp): the visibility buffer's operation (3D
// rasterization keeps depth bits << 32 | triangle id per pixel with atomicMin). One atomicMin per
// element to its own 64-bit word (distinct addresses, coalesced, as a tile of pixels is).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require

layout(local_size_x = 256) in;
layout(push_constant) uniform Push {
  uint elements;  // atomic operations = 64-bit words
  uint iterations;
  uint sentinel;
  uint pad;
}
push;

layout(std430) buffer Dst { uint64_t keys[]; };

void main() {
  const uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint i = gl_GlobalInvocationID.x; i < push.elements; i += stride)
    atomicMin(keys[i], (uint64_t(i ^ push.sentinel) << 32) | uint64_t(i));
}
