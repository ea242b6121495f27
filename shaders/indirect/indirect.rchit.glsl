#version 460
// Indirect light, closest hit: the hit's t and draw-order triangle id (IdBase, bound by name like
// the ray generation shader's bindings; primary_raycast.glsl.inc explains the table).
#extension GL_EXT_ray_tracing : require

readonly buffer IdBase { uint idBase[]; };
layout(location = 0) rayPayloadInEXT uvec2 hitTId;

void main() {
  const uint id = idBase[idBase[uint(gl_InstanceCustomIndexEXT)] + uint(gl_GeometryIndexEXT)] + uint(gl_PrimitiveID);
  hitTId = uvec2(floatBitsToUint(gl_HitTEXT), id);
}
