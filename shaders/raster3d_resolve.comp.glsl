#version 460
// After 3D rasterization: each pixel's reverse-Z depth from its nearest hit, D/t − C (camera.h;
// for an orthographic view the affine D − C·t of its matrix, with that matrix's C and D), and 0 (the far plane, the prepass's clear value) where no triangle covers it. The frame copies
// this buffer into its depth image, so light culling, shadows and shading read depth as after the
// hardware prepass.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared/gpu_types.h"

layout(local_size_x = 64) in;
uniform Constants { Raster3dConstants r3; };
readonly buffer Visibility { uint64_t vis[]; };
writeonly buffer Depth { float depth[]; };

void main() {
  const uint pixel = gl_GlobalInvocationID.x;
  if (pixel >= r3.width * r3.height) return;
  const uint64_t key = vis[pixel];
  float z = 0.0;
  if (key != ~0ul) {
    const float t = uintBitsToFloat(uint(key >> 32));
    z = clamp(r3.projection == kProjectionOrthographic ? r3.depth.w - r3.depth.z * t : r3.depth.w / t - r3.depth.z,
              0.0, 1.0);
  }
  depth[pixel] = z;
}
