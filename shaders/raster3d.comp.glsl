#version 460
// Primary visibility by 3D rasterization (raster3d.glsl.inc), brute force over each triangle's
// screen box (the paper's "3DR"). Two dispatches of this shader:
//   PASS 0: one thread per triangle: setup, screen box; a box of at most smallArea pixels is
//           rasterized by the thread itself, a larger one is appended to the big-triangle list
//           (whose count is the x of an indirect dispatch);
//   PASS 1: one workgroup per big triangle: its threads stride over the box.
// A covered pixel within [znear, zfar] takes atomicMin of (t bits << 32 | triangle id): the nearest
// hit, ties to the smaller id, the same on every run (t > 0, and positive floats order like their
// bits). ANALYSIS = 1 also counts (kR3dCounter*) and adds coverage per pixel (depth-test free).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared/gpu_types.h"
#include "raster3d.glsl.inc"

layout(constant_id = 0) const uint PASS = 0;
layout(constant_id = 1) const uint ANALYSIS = 0;
layout(local_size_x = 64) in;

layout(set = 0, binding = 0) uniform Constants { Raster3dConstants r3; };
layout(set = 0, binding = 1) readonly buffer Triangles { vec4 triVerts[]; };  // 3 per triangle, xyz world
layout(set = 0, binding = 2) buffer Visibility { uint64_t vis[]; };
layout(set = 0, binding = 3) buffer Big { uint bigDispatch[3]; uint bigIds[]; };
layout(set = 0, binding = 4) buffer Counters { uint64_t counters[kR3dCounterCount]; };
layout(set = 0, binding = 5) buffer Coverage { uint coverage[]; };

void rasterizePixels(uint id, R3dSetup s, ivec2 lo, ivec2 hi, uint first, uint stride) {
  const uint w = uint(hi.x - lo.x + 1), h = uint(hi.y - lo.y + 1), area = w * h;
  uint fallbacks = 0u, covered = 0u, atomics = 0u;
  for (uint i = first; i < area; i += stride) {
    const uint x = uint(lo.x) + i % w, y = uint(lo.y) + i / w;
    float t;
    if (!r3dCovers(s, float(x), float(y), r3, t, fallbacks)) continue;
    const uint pixel = y * r3.width + x;
    if (ANALYSIS == 1) {
      atomicAdd(coverage[pixel], 1u);
      ++covered;
    }
    if (t < r3.depth.x || t > r3.depth.y) continue;  // the near and far planes clip
    atomicMin(vis[pixel], (uint64_t(floatBitsToUint(t)) << 32) | uint64_t(id));
    ++atomics;
  }
  if (ANALYSIS == 1) {
    const uint tested = first < area ? (area - first + stride - 1) / stride : 0u;
    atomicAdd(counters[kR3dCounterPixelsTested], uint64_t(tested));
    atomicAdd(counters[kR3dCounterEdgeEvals], uint64_t(3u * tested));
    atomicAdd(counters[kR3dCounterFallbacks], uint64_t(fallbacks));
    atomicAdd(counters[kR3dCounterCovered], uint64_t(covered));
    atomicAdd(counters[kR3dCounterAtomics], uint64_t(atomics));
  }
}

void main() {
  uint id;
  uint first = 0u, stride = 1u;
  if (PASS == 0) {
    id = gl_GlobalInvocationID.x;
    if (id >= r3.triangleCount) return;
  } else {
    id = bigIds[gl_WorkGroupID.x];
    first = gl_LocalInvocationID.x;
    stride = gl_WorkGroupSize.x;
  }
  R3dSetup s;
  if (!r3dSetup(triVerts[3u * id].xyz, triVerts[3u * id + 1u].xyz, triVerts[3u * id + 2u].xyz, r3, s)) return;
  ivec2 lo, hi;
  r3dScreenBox(s, r3, lo, hi);
  if (hi.x < lo.x || hi.y < lo.y) return;
  if (PASS == 0) {
    if (ANALYSIS == 1) atomicAdd(counters[kR3dCounterSetups], 1ul);
    const uint area = uint(hi.x - lo.x + 1) * uint(hi.y - lo.y + 1);
    if (area > r3.smallArea) {
      bigIds[atomicAdd(bigDispatch[0], 1u)] = id;
      if (ANALYSIS == 1) atomicAdd(counters[kR3dCounterBig], 1ul);
      return;
    }
  }
  rasterizePixels(id, s, lo, hi, first, stride);
}
