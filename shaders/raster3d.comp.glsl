#version 460
// Primary visibility by 3D rasterization (raster3d.glsl.inc), brute force over each triangle's
// screen box (the paper's "3DR"), or binned (BINNED = 1: of a big box only the 8x8 tiles the
// triangle can touch are rasterized; the test runs per tile in PASS 1, so PASS 0 stays one short
// loop per triangle). Two dispatches of this shader:
//   PASS 0: one thread per triangle: setup and screen box; a box of at most smallArea pixels is
//           rasterized by the thread itself; a larger one is cut into 8x8-pixel tiles, appended
//           as (triangle, tile) work items (one atomicAdd per triangle). When the list is full
//           the thread rasterizes its box itself: slower, never a dropped pixel (counted).
//   PASS 1: tileWorkgroups workgroups of 64 threads stride over the work items, one pixel each.
// A covered pixel within [znear, zfar] takes atomicMin of (t bits << 32 | triangle id): the nearest
// hit, ties to the smaller id, the same on every run (t > 0, and positive floats order like their
// bits). ANALYSIS = 1 also counts (kR3dCounter*) and adds coverage per pixel (depth-test free).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared/gpu_types.h"

layout(constant_id = 0) const uint PASS = 0;
layout(constant_id = 1) const uint ANALYSIS = 0;
layout(constant_id = 2) const uint FALLBACK = 1;  // 0: no fp64 re-evaluation (to measure what it prevents)
layout(constant_id = 3) const uint BINNED = 0;    // 1: only the 8x8 tiles of a big box that the triangle can touch
const bool R3D_FALLBACK = FALLBACK == 1;
#include "raster3d.glsl.inc"
layout(local_size_x = 64) in;

layout(set = 0, binding = 0) uniform Constants { Raster3dConstants r3; };
layout(set = 0, binding = 1) readonly buffer Triangles { vec4 triVerts[]; };  // 3 per triangle, xyz world
layout(set = 0, binding = 2) buffer Visibility { uint64_t vis[]; };
layout(set = 0, binding = 3) buffer Items { uint itemCount; uint itemPad[3]; uvec2 items[]; };  // (id, tx | ty << 16)
layout(set = 0, binding = 4) buffer Counters { uint64_t counters[kR3dCounterCount]; };
layout(set = 0, binding = 5) buffer Coverage { uint coverage[]; };
layout(set = 0, binding = 6) buffer Tested { uint testedPerPixel[]; };  // ANALYSIS: pixel tests per pixel

struct Tally {
  uint tested, fallbacks, covered, atomics;
};

void testPixel(uint id, R3dSetup s, uint x, uint y, inout Tally tally) {
  ++tally.tested;
  const uint pixel = y * r3.width + x;
  if (ANALYSIS == 1) atomicAdd(testedPerPixel[pixel], 1u);
  float t;
  if (!r3dCovers(s, float(x), float(y), r3, t, tally.fallbacks)) return;
  if (ANALYSIS == 1) {
    atomicAdd(coverage[pixel], 1u);
    ++tally.covered;
  }
  if (!(t >= r3.depth.x && t <= r3.depth.y)) return;  // the near and far planes clip (and NaN)
  atomicMin(vis[pixel], (uint64_t(floatBitsToUint(t)) << 32) | uint64_t(id));
  ++tally.atomics;
}

void flush(Tally tally) {
  if (ANALYSIS == 0) return;
  atomicAdd(counters[kR3dCounterPixelsTested], uint64_t(tally.tested));
  atomicAdd(counters[kR3dCounterEdgeEvals], uint64_t(3u * tally.tested));
  atomicAdd(counters[kR3dCounterFallbacks], uint64_t(tally.fallbacks));
  atomicAdd(counters[kR3dCounterCovered], uint64_t(tally.covered));
  atomicAdd(counters[kR3dCounterAtomics], uint64_t(tally.atomics));
}

// Binning (BINNED = 1): can the triangle cover a pixel centre of the 8x8 tile whose first centre
// is (x0, y0), clamped to hi? V_i is linear in (x, y), so over the tile's centres it is largest
// at one of the four corner centres. If for some edge every corner has V_i < -bound (the rounding
// bound of r3dCovers at the tile's far corner, which is the largest), no centre of the tile can
// be inside, not even by the tie rule or the fp64 fallback: the tile is skipped. Conservative, so
// the binned result equals brute force bit for bit.
bool tileMayBeCovered(R3dSetup s, uint x0, uint y0, ivec2 hi) {
  const float xa = float(x0), ya = float(y0);
  const float xb = float(min(x0 + 7u, uint(hi.x))), yb = float(min(y0 + 7u, uint(hi.y)));
  const vec3 bound = kR3dBound * (s.errA + xb * s.errB + yb * s.errC);
  const vec3 v00 = s.rowA + xa * s.rowB + ya * s.rowC, v10 = s.rowA + xb * s.rowB + ya * s.rowC;
  const vec3 v01 = s.rowA + xa * s.rowB + yb * s.rowC, v11 = s.rowA + xb * s.rowB + yb * s.rowC;
  const vec3 vmax = max(max(v00, v10), max(v01, v11));
  // 2·bound: the corners' own float evaluation is rounded too (each within bound of exact).
  return all(greaterThanEqual(vmax, -2.0 * bound));
}

bool setupTriangle(uint id, out R3dSetup s, out ivec2 lo, out ivec2 hi) {
  if (!r3dSetup(triVerts[3u * id].xyz, triVerts[3u * id + 1u].xyz, triVerts[3u * id + 2u].xyz, r3, s)) return false;
  r3dScreenBox(s, r3, lo, hi);
  return hi.x >= lo.x && hi.y >= lo.y;
}

void perTriangle() {
  const uint id = gl_GlobalInvocationID.x;
  if (id >= r3.triangleCount) return;
  R3dSetup s;
  ivec2 lo, hi;
  if (!setupTriangle(id, s, lo, hi)) return;
  if (ANALYSIS == 1) atomicAdd(counters[kR3dCounterSetups], 1ul);
  const uint w = uint(hi.x - lo.x + 1), h = uint(hi.y - lo.y + 1);
  if (w * h > r3.smallArea) {
    const uint tw = (w + 7u) / 8u, th = (h + 7u) / 8u;
    const uint n = tw * th;
    const uint first = atomicAdd(itemCount, n);
    if (ANALYSIS == 1) atomicAdd(counters[kR3dCounterBig], 1ul);
    if (first + n <= r3.itemCapacity) {
      for (uint ty = 0u; ty < th; ++ty)
        for (uint tx = 0u; tx < tw; ++tx) items[first + ty * tw + tx] = uvec2(id, tx | (ty << 16));
      return;
    }
    if (ANALYSIS == 1) atomicAdd(counters[kR3dCounterOverflow], 1ul);
  }
  Tally tally = Tally(0u, 0u, 0u, 0u);
  for (uint y = uint(lo.y); y <= uint(hi.y); ++y)
    for (uint x = uint(lo.x); x <= uint(hi.x); ++x) testPixel(id, s, x, y, tally);
  flush(tally);
}

void perTile() {
  const uint count = min(itemCount, r3.itemCapacity);
  Tally tally = Tally(0u, 0u, 0u, 0u);
  for (uint item = gl_WorkGroupID.x; item < count; item += gl_NumWorkGroups.x) {
    const uvec2 it = items[item];
    R3dSetup s;
    ivec2 lo, hi;
    if (!setupTriangle(it.x, s, lo, hi)) continue;  // never: PASS 0 set it up the same way
    const uint x0 = uint(lo.x) + (it.y & 0xFFFFu) * 8u, y0 = uint(lo.y) + (it.y >> 16) * 8u;
    // Binned: the whole workgroup skips a tile the triangle cannot touch (uniform branch).
    if (BINNED == 1 && !tileMayBeCovered(s, x0, y0, hi)) continue;
    const uint x = x0 + gl_LocalInvocationID.x % 8u, y = y0 + gl_LocalInvocationID.x / 8u;
    if (x <= uint(hi.x) && y <= uint(hi.y)) testPixel(it.x, s, x, y, tally);
  }
  flush(tally);
}

void main() {
  if (PASS == 0)
    perTriangle();
  else
    perTile();
}
