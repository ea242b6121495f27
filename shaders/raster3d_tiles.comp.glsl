#version 460
// 3dr-binned, last: one workgroup per screen 8x8 tile, a pixel per thread. The tile's triangles
// (the list the count-scan-fill passes built) are set up 64 at a time into shared memory; each
// thread keeps its pixel's nearest key in a register and does one atomicMin at the end (against
// the small triangles PASS 0 rasterized directly). Shared memory lives only in this shader (and the
// scan's), so the per-triangle and per-item passes keep full occupancy.
// EARLYZ (2dr-binned always, 3dr-binned with r3d_early_z): each thread starts from its pixel's key
// so far (the small triangles of PASS 0), and before each batch the tile's farthest depth so far is
// reduced in shared memory; a triangle whose nearest vertex depth (less a rounding margin) is
// farther than it gives every pixel a larger t, hence a larger key whatever its id, and is skipped
// (counted as blocks_culled_early_z). The result is the same bit for bit.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared/gpu_types.h"

#include "raster3d_common.glsl.inc"
layout(local_size_x = 64) in;
layout(constant_id = 6) const uint EARLYZ = 0;

shared R3dSetup sSetup[64];
shared ivec4 sBox[64];  // lo, hi; empty (hi < lo) for a slot past the batch
shared uint sId[64];
shared uint sHit[64];  // ANALYSIS: did entry j cover a pixel of the tile (bins refined without a hit)
shared float sZmin[64];  // EARLYZ: the triangle's nearest vertex depth, less its rounding margin
shared uint sTileMax;    // EARLYZ: max over the tile's pixels of their key's t bits

void main() {
  const uint tile = gl_WorkGroupID.x, T = tileCount();
  if (tile >= T) return;
  const uint first = bins[T + tile];
  const uint end = min(first + bins[tile], r3.itemCapacity);
  const uint x = (tile % tilesX()) * 8u + gl_LocalInvocationID.x % 8u;
  const uint y = (tile / tilesX()) * 8u + gl_LocalInvocationID.x / 8u;
  Tally tally = Tally(0u, 0u, 0u, 0u);
  const bool onScreen = x < r3.width && y < r3.height;
  uint64_t best = EARLYZ == 1u && onScreen ? vis[y * r3.width + x] : ~0ul;
  const uint64_t before = best;
  uint earlyZ = 0u;
  for (uint base = first; base < end; base += 64u) {
    const uint k = base + gl_LocalInvocationID.x;
    ivec4 box = ivec4(0, 0, -1, -1);
    if (k < end) {
      const uint id = binList[k];
      R3dSetup s;
      ivec2 lo, hi;
      float zmin = 0.0;
      if (setupTriangle(id, s, lo, hi)) {
        box = ivec4(lo, hi);
        const vec3 f = r3.forward.xyz;
        const vec3 z = vec3(dot(s.p0, f), dot(s.p1, f), dot(s.p2, f));
        zmin = min(z.x, min(z.y, z.z));
        zmin -= 16.0 * 5.9604644775390625e-8 * (abs(zmin) + dot(abs(f), max(abs(s.p0), max(abs(s.p1), abs(s.p2)))));
      }
      sSetup[gl_LocalInvocationID.x] = s;
      sId[gl_LocalInvocationID.x] = id;
      sZmin[gl_LocalInvocationID.x] = zmin;
    }
    sBox[gl_LocalInvocationID.x] = box;
    if (ANALYSIS == 1) sHit[gl_LocalInvocationID.x] = 0u;
    if (EARLYZ == 1u && gl_LocalInvocationID.x == 0u) sTileMax = 0u;
    barrier();
    if (EARLYZ == 1u) {
      if (onScreen) atomicMax(sTileMax, uint(best >> 32));
      barrier();
    }
    // The tile's farthest depth so far (0xFFFFFFFF: a pixel has no hit yet, nothing is skipped).
    const uint tileMax = EARLYZ == 1u ? sTileMax : 0xFFFFFFFFu;
    const uint n = min(64u, end - base);
    for (uint j = 0u; j < n; ++j) {
      const ivec4 b = sBox[j];
      if (EARLYZ == 1u && tileMax != 0xFFFFFFFFu && sZmin[j] > uintBitsToFloat(tileMax)) {
        if (gl_LocalInvocationID.x == 0u) ++earlyZ;  // uniform: every thread skips it
        continue;
      }
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
  if (ANALYSIS == 1 && EARLYZ == 1u && earlyZ > 0u) atomicAdd(counters[kR3dCounterCulledEarlyZ], uint64_t(earlyZ));
  if (best < before && onScreen) {
    atomicMin(vis[y * r3.width + x], best);
    ++tally.atomics;
  }
  flush(tally);
}
