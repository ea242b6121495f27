#version 460
// The device's ray rates on a scene's TLAS (gpu/peaks.cpp addRayPeaks), through the ray-tracing
// pipeline, one ray per launch: MODE 0 camera rays through the pixels of a width x height image
// (coherent; closest hit), 1 rays from uniformly random points of the scene's bounds in uniformly
// random directions (incoherent; closest hit), 2 the same rays as occlusion rays (the first hit
// ends them, as shadow and AO rays). No hit shader runs: the rate is traversal and intersection.
// Each launch writes whether its ray missed, so no ray can be dropped.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_tracing : require
#include "shared/bindings.h"

layout(constant_id = 0) const uint MODE = 0u;

layout(binding = HB_PEAKS_TLAS) uniform accelerationStructureEXT tlas;
layout(std430, binding = HB_PEAKS_DST) buffer Dst { uint missedOut[]; };
layout(std140, binding = HB_PEAKS_PARAMS) uniform Params {
  vec4 eye;      // xyz; w unused
  vec4 forward;  // xyz, the camera's look direction; w = the rays' tMax
  vec4 right;    // xyz scaled by tan(xfov / 2)
  vec4 up;       // xyz scaled by tan(yfov / 2)
  vec4 lo, hi;   // the scene's bounds
}
p;

layout(location = 0) rayPayloadEXT uint missed;  // the miss shader (shadows.rmiss) sets 1

// PCG hash (Jarzynski and Olano 2020): a well-mixed 32-bit value per input.
uint pcg(uint v) {
  const uint state = v * 747796405u + 2891336453u;
  const uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}
float unit(inout uint s) {
  s = pcg(s);
  return float(s >> 8) * (1.0 / 16777216.0);
}

void main() {
  const uvec2 id = gl_LaunchIDEXT.xy, size = gl_LaunchSizeEXT.xy;
  const uint index = id.y * size.x + id.x;
  vec3 origin, dir;
  if (MODE == 0u) {
    const vec2 ndc = (vec2(id) + 0.5) / vec2(size) * 2.0 - 1.0;
    origin = p.eye.xyz;
    dir = normalize(p.forward.xyz + ndc.x * p.right.xyz - ndc.y * p.up.xyz);
  } else {
    uint s = index * 9781u + 0x9E3779B9u;
    origin = mix(p.lo.xyz, p.hi.xyz, vec3(unit(s), unit(s), unit(s)));
    const float z = 2.0 * unit(s) - 1.0, phi = 6.28318530718 * unit(s);
    const float r = sqrt(max(0.0, 1.0 - z * z));
    dir = vec3(r * cos(phi), r * sin(phi), z);
  }
  missed = 0u;
  const uint flags = gl_RayFlagsOpaqueEXT | gl_RayFlagsSkipClosestHitShaderEXT |
                     (MODE == 2u ? gl_RayFlagsTerminateOnFirstHitEXT : 0u);
  traceRayEXT(tlas, flags, 0xFF, 0, 0, 0, origin, 0.0, dir, p.forward.w, 0);
  missedOut[index] = missed;
}
