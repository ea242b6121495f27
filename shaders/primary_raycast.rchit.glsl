#version 460
// primary=raycast, closest hit: the hit's t and draw-order triangle id (primary_raycast.glsl.inc).
#extension GL_GOOGLE_include_directive : require
#include "primary_raycast_pipeline.glsl.inc"
layout(location = 0) rayPayloadInEXT uvec2 hitTId;

void main() {
  hitTId = uvec2(floatBitsToUint(gl_HitTEXT),
                 triangleId(uint(gl_InstanceCustomIndexEXT), uint(gl_GeometryIndexEXT), uint(gl_PrimitiveID)));
}
