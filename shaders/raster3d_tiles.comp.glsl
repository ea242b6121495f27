#version 460
// 3dr-binned, last: one workgroup per screen 8x8 tile, a pixel per thread. The tile's triangles
// (the list the count-scan-fill passes built) are set up 64 at a time into shared memory; each
// thread keeps its pixel's nearest key in a register and does one atomicMin at the end (against
// the small triangles PASS 0 rasterized directly). Shared memory lives only in this shader (and the
// scan's), so the per-triangle and per-item passes keep full occupancy.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared/gpu_types.h"

#include "raster3d_common.glsl.inc"
layout(local_size_x = 64) in;

shared R3dSetup sSetup[64];
shared ivec4 sBox[64];  // lo, hi; empty (hi < lo) for a slot past the batch
shared uint sId[64];
shared uint sHit[64];  // ANALYSIS: did entry j cover a pixel of the tile (bins refined without a hit)

void main() {
  const uint tile = gl_WorkGroupID.x, T = tileCount();
  if (tile >= T) return;
  const uint first = bins[T + tile];
  const uint end = min(first + bins[tile], r3.itemCapacity);
  const uint x = (tile % tilesX()) * 8u + gl_LocalInvocationID.x % 8u;
  const uint y = (tile / tilesX()) * 8u + gl_LocalInvocationID.x / 8u;
  Tally tally = Tally(0u, 0u, 0u, 0u);
  uint64_t best = ~0ul;
  for (uint base = first; base < end; base += 64u) {
    const uint k = base + gl_LocalInvocationID.x;
    ivec4 box = ivec4(0, 0, -1, -1);
    if (k < end) {
      const uint id = binList[k];
      R3dSetup s;
      ivec2 lo, hi;
      if (setupTriangle(id, s, lo, hi)) box = ivec4(lo, hi);
      sSetup[gl_LocalInvocationID.x] = s;
      sId[gl_LocalInvocationID.x] = id;
    }
    sBox[gl_LocalInvocationID.x] = box;
    if (ANALYSIS == 1) sHit[gl_LocalInvocationID.x] = 0u;
    barrier();
    const uint n = min(64u, end - base);
    for (uint j = 0u; j < n; ++j) {
      const ivec4 b = sBox[j];
      if (int(x) < b.x || int(y) < b.y || int(x) > b.z || int(y) > b.w) continue;
      uint64_t key;
      const uint coveredBefore = tally.covered;
      if (pixelKey(sId[j], sSetup[j], x, y, tally, key)) best = min(best, key);
      if (ANALYSIS == 1 && tally.covered != coveredBefore) atomicOr(sHit[j], 1u);
    }
    barrier();
    if (ANALYSIS == 1 && gl_LocalInvocationID.x < n) {  // each thread reads only its own slot
      atomicAdd(counters[kR3dCounterBinsRefined], 1ul);
      if (sHit[gl_LocalInvocationID.x] == 0u) atomicAdd(counters[kR3dCounterBinsEmpty], 1ul);
    }
  }
  if (best != ~0ul && x < r3.width && y < r3.height) {
    atomicMin(vis[y * r3.width + x], best);
    ++tally.atomics;
  }
  flush(tally);
}
