#version 460
// Light culling, first step (frame/passes/light_culling.h): every light in view space once per frame
// (culling.glsl.inc toViewLight), so that each tile's test reads 48 bytes and transforms nothing.
// zbin: the depth-sorted lights (after zbin_sort.comp.glsl), so indices stay sorted indices.
#extension GL_GOOGLE_include_directive : require
#include "culling.glsl.inc"
layout(local_size_x = 64) in;
layout(constant_id = 0) const uint LIST_MODE = 0;  // kList*

uniform Frame { FrameConstants frame; };
readonly buffer Lights { GpuLight lights[]; };
readonly buffer SortedLights { GpuLight sortedLights[]; };
writeonly buffer ViewLights { GpuViewLight viewLights[]; };
// The range spheres alone (xyz, range; directional: +inf), what every tile reads first.
writeonly buffer ViewSpheres { vec4 viewSpheres[]; };
layout(push_constant) uniform Push { uint lightCount; } pc;

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i >= min(pc.lightCount, kMaxLights)) return;
  GpuViewLight v;
  if (LIST_MODE == kListZbin) v = toViewLight(sortedLights[i], frame.view);
  else v = toViewLight(lights[i], frame.view);
  viewLights[i] = v;
  viewSpheres[i] = vec4(v.positionRange.xyz, v.type == kLightDirectional ? uintBitsToFloat(0x7F800000u) : v.positionRange.w);
}
