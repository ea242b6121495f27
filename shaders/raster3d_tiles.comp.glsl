#version 460
// 3dr-binned, last: one workgroup per screen 8x8 tile, a pixel per thread. The tile's triangles
// (the list the count-scan-fill passes built; PASS 0 made their setups) are read 64 at a time into
// shared memory; each thread keeps its pixel's nearest key in a register and does one atomicMin at
// the end (against the small triangles PASS 0 rasterized directly). Shared memory lives only in
// this shader (and the scan's), so the per-triangle and per-item passes keep full occupancy.
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

// The batch's setups, as 16-byte vectors (one shared load each): what the fast path below reads,
// the rows, the bound and the box. A pixel that needs the exact test reads the whole setup from
// PASS 0's record (setups[sSpan[j]]).
shared vec4 sRowA[64];   // rowA, the plane's offset
shared vec4 sRowB[64];   // rowB
shared uint sId[64];     // the triangle id
shared uint sSpan[64];   // its span: where its setup is kept
shared vec4 sRowC[64];   // rowC
shared vec4 sBound[64];  // the largest rounding bound of r3dCovers over the tile (with a margin), EARLYZ: zmin
shared vec4 sPlane[64];  // the plane's normal
shared ivec4 sBox[64];  // lo, hi; empty (hi < lo) for a slot past the batch
shared uint sHit[64];   // ANALYSIS: did entry j cover a pixel of the tile (bins refined without a hit)
shared uint sTileMax;   // EARLYZ: max over the tile's pixels of their key's t bits

// The fast path: timed frames (no counts), 3D rasterization of a perspective view. V_i is evaluated
// exactly as r3dCovers does (precise: the same operations), and its rounding bound there grows with
// x and y (every term >= 0, each operation monotone), so at this tile's pixels it is at most the
// bound at the tile's last pixel; that, times 1.001 for a compiler that contracts the two
// evaluations differently (a few units in the last place), is sBound. An edge with V_i < −sBound
// is outside without the fp64 fallback, so the pixel is not covered; V_i > sBound on all three
// edges is inside with no fallback and no tie. Anything else (a pixel within rounding of an edge)
// takes r3dCovers itself. The key is the same bit for bit.
const bool kFastPath = ANALYSIS == 0u && !R3D_2D && R3D_PROJECTION == kProjectionPerspective;

void main() {
  const uint tile = gl_WorkGroupID.x, T = tileCount();
  if (tile >= T) return;
  const uint first = bins[T + tile];
  const uint end = min(first + bins[tile], r3.itemCapacity);
  const uint x = (tile % tilesX()) * 8u + gl_LocalInvocationID.x % 8u;
  const uint y = (tile / tilesX()) * 8u + gl_LocalInvocationID.x / 8u;
  const uint lastX = min((tile % tilesX()) * 8u + 7u, r3.width - 1u), lastY = min((tile / tilesX()) * 8u + 7u, r3.height - 1u);
  Tally tally = Tally(0u, 0u, 0u, 0u);
  const bool onScreen = x < r3.width && y < r3.height;
  uint64_t best = EARLYZ == 1u && onScreen ? vis[y * r3.width + x] : ~0ul;
  const uint64_t before = best;
  uint earlyZ = 0u;
  for (uint base = first; base < end; base += 64u) {
    const uint k = base + gl_LocalInvocationID.x, lid = gl_LocalInvocationID.x;
    ivec4 box = ivec4(0, 0, -1, -1);
    if (k < end) {
      // PASS 0's setup of the entry's triangle (binList holds its span).
      const uint span = binList[k];
      box = setups[span].box;
      const vec4 errA = setups[span].errA;
      const vec3 bound = kR3dBound * (errA.xyz + float(lastX) * setups[span].errB.xyz + float(lastY) * setups[span].errC.xyz) * 1.001;
      sRowA[lid] = setups[span].rowA;
      sRowB[lid] = setups[span].rowB;
      sRowC[lid] = setups[span].rowC;
      sBound[lid] = vec4(bound, errA.w);
      sPlane[lid] = setups[span].planeNormal;
      sId[lid] = setups[span].info.x;
      sSpan[lid] = span;
    }
    sBox[lid] = box;
    if (ANALYSIS == 1) sHit[lid] = 0u;
    if (EARLYZ == 1u && lid == 0u) sTileMax = 0u;
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
      if (EARLYZ == 1u && tileMax != 0xFFFFFFFFu && sBound[j].w > uintBitsToFloat(tileMax)) {
        if (lid == 0u) ++earlyZ;  // uniform: every thread skips it
        continue;
      }
      if (int(x) < b.x || int(y) < b.y || int(x) > b.z || int(y) > b.w) continue;
      const uint id = sId[j];
      if (kFastPath) {
        const float fx = float(x), fy = float(y);
        precise vec3 v = sRowA[j].xyz + fx * sRowB[j].xyz + fy * sRowC[j].xyz;  // as r3dCovers
        const vec3 bound = sBound[j].xyz;
        if (any(lessThan(v, -bound))) continue;  // outside (NaN goes on to r3dCovers)
        if (all(greaterThan(v, bound))) {
          const float t = r3dPerspectiveDepth(sRowA[j].w, sPlane[j].xyz, fx, fy, r3);
          if (t >= r3.depth.x && t <= r3.depth.y) best = min(best, (uint64_t(floatBitsToUint(t)) << 32) | uint64_t(id));
          continue;
        }
      }
      uint64_t key;
      const uint coveredBefore = tally.covered;
      ivec2 lo, hi;
      if (pixelKey(id, loadSetupRecord(sSpan[j], lo, hi), x, y, tally, key)) best = min(best, key);
      if (ANALYSIS == 1 && tally.covered != coveredBefore) atomicOr(sHit[j], 1u);
    }
    barrier();
    if (ANALYSIS == 1 && lid < n) {  // each thread reads only its own slot
      atomicAdd(counters[kR3dCounterBinsRefined], 1ul);
      if (sHit[lid] == 0u) atomicAdd(counters[kR3dCounterBinsEmpty], 1ul);
    }
  }
  if (ANALYSIS == 1 && EARLYZ == 1u && earlyZ > 0u) atomicAdd(counters[kR3dCounterCulledEarlyZ], uint64_t(earlyZ));
  if (best < before && onScreen) {
    atomicMin(vis[y * r3.width + x], best);
    ++tally.atomics;
  }
  flush(tally);
}
