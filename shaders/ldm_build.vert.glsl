#version 460
// Layered depth maps, the hardware build (Aalund et al. 2015, Sect. 3; ldm_build=hardware): one
// instanced draw of the scene over the N maps, gl_InstanceIndex the map. Orthographic along the
// map's dir over the scene's bounding sphere (gpu_types.h LdmMap): NDC x = (p − c)·right / r,
// y = −(p − c)·up / r (Vulkan's y down), z a constant 0.5 so that nothing is clipped in depth (the
// sphere holds the scene). The fragment shader gets the map and the depth z = (p − c)·dir + r, which
// is affine along the map (interpolated exactly by the rasterizer up to rounding).
#extension GL_GOOGLE_include_directive : require
#include "shared/gpu_types.h"

layout(location = 0) in vec3 inPosition;
layout(push_constant) uniform Push { DrawConstants draw; };
readonly buffer Maps { LdmMap maps[]; };

layout(location = 0) flat out uint outMap;
layout(location = 1) out float outDepth;

void main() {
  const LdmMap m = maps[gl_InstanceIndex];
  const vec3 p = (draw.model * vec4(inPosition, 1.0)).xyz - m.centreRadius.xyz;
  const float r = m.centreRadius.w;
  gl_Position = vec4(dot(p, m.right.xyz) / r, -dot(p, m.up.xyz) / r, 0.5, 1.0);
  outMap = uint(gl_InstanceIndex);
  outDepth = dot(p, m.dir.xyz) + r;
}
