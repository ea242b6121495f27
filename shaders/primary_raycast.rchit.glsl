#version 460
// primary=raycast, closest hit: the hit's t and draw-order triangle id (primary_raycast.glsl.inc).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_tracing : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared/gpu_types.h"

layout(constant_id = 0) const uint ANALYSIS = 0;
#include "primary_raycast.glsl.inc"
layout(location = 0) rayPayloadInEXT uvec2 hitTId;

void main() {
  hitTId = uvec2(floatBitsToUint(gl_HitTEXT),
                 triangleId(uint(gl_InstanceCustomIndexEXT), uint(gl_GeometryIndexEXT), uint(gl_PrimitiveID)));
}
