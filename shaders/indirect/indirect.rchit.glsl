#version 460
// Indirect light, closest hit: the hit's t and draw-order triangle id (idBase, binding 16 of the
// indirect pass's set; primary_raycast.glsl.inc explains the table).
// 16 is HB_INDIRECT_ID_BASE (shared/bindings.h), written as the number here alone: this shader
// includes nothing, and an #include would need GL_GOOGLE_include_directive, whose OpSourceExtension
// lines would change its SPIR-V.
#extension GL_EXT_ray_tracing : require

layout(set = 0, binding = 16) readonly buffer IdBase { uint idBase[]; };
layout(location = 0) rayPayloadInEXT uvec2 hitTId;

void main() {
  const uint id = idBase[idBase[uint(gl_InstanceCustomIndexEXT)] + uint(gl_GeometryIndexEXT)] + uint(gl_PrimitiveID);
  hitTId = uvec2(floatBitsToUint(gl_HitTEXT), id);
}
