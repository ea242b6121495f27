#version 460
// After 3D rasterization (or the ray cast): each pixel's reverse-Z depth from its nearest hit, D/t − C
// (camera.h; for an orthographic view the affine D − C·t of its matrix, with that matrix's C and
// D), and 0 (the far plane, the prepass's clear value) where no triangle covers it, written
// straight into the frame's depth image as gl_FragDepth (depth test ALWAYS), so light culling,
// shadows and shading read depth as after the hardware prepass. A depth format cannot be a storage
// image, so compute cannot write it; this draw replaced a compute resolve into a buffer and a
// buffer-to-image copy, which ran at a few per cent of the device's bandwidth.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared/gpu_types.h"
#include "shared/bindings.h"

layout(set = 0, binding = HB_R3D_RESOLVE_CONSTANTS) uniform Constants { Raster3dConstants r3; };
layout(set = 0, binding = HB_R3D_RESOLVE_VISIBILITY) readonly buffer Visibility { uint64_t vis[]; };

void main() {
  const uvec2 p = uvec2(gl_FragCoord.xy);
  const uint64_t key = vis[p.y * r3.width + p.x];
  float z = 0.0;
  if (key != ~0ul) {
    const float t = uintBitsToFloat(uint(key >> 32));
    z = clamp(r3.projection == kProjectionOrthographic ? r3.depth.w - r3.depth.z * t : r3.depth.w / t - r3.depth.z,
              0.0, 1.0);
  }
  gl_FragDepth = z;
}
