#version 460
// Primary visibility by 3D rasterization (raster3d.glsl.inc) or by the paper's 2D homogeneous
// baseline (METHOD2D), brute force over each triangle's screen box ("3dr", "2dr") or binned into
// screen tiles ("3dr-binned"). One shader, dispatched per PASS:
//   Brute force (BINNED = 0):
//   PASS 0: one thread per triangle: setup and screen box; a box of at most smallArea pixels is
//           rasterized by the thread itself; a larger one is cut into 8x8-pixel tiles of its box,
//           appended as (triangle, tile) work items (one atomicAdd per triangle). When the list is
//           full the thread rasterizes its box itself: slower, never a dropped pixel (counted).
//   PASS 1: tileWorkgroups workgroups of 64 threads stride over the work items, one pixel each,
//           one atomicMin per covered pixel.
//   Binned (BINNED = 1), count-scan-fill into the screen's 8x8 tiles:
//   PASS 0: as above for small boxes; a larger box counts +1 on each screen tile it overlaps and
//           the triangle can touch (tileMayBeCovered: its edge functions at the tile's corners).
//   PASS 2: one workgroup: exclusive prefix sum of the counts (each tile's first list entry).
//   PASS 3: one thread per triangle again: the same tiles, each given its triangle id at
//           offset + atomicAdd(cursor). An entry past the list's capacity is rasterized by the
//           thread itself (counted, never dropped).
//   PASS 1: one workgroup per screen tile, a pixel per thread: the tile's triangles are set up 64 at
//           a time into shared memory, each thread keeps its pixel's nearest key in a register and
//           does one atomicMin at the end (against the small triangles' results).
// A covered pixel within [znear, zfar] takes atomicMin of (t bits << 32 | triangle id): the nearest
// hit, ties to the smaller id, the same on every run and for both orders of work (t > 0, and
// positive floats order like their bits), so binned equals brute force bit for bit.
// ANALYSIS = 1 also counts (kR3dCounter*) and adds coverage per pixel (depth-test free).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared/gpu_types.h"

layout(constant_id = 0) const uint PASS = 0;
layout(constant_id = 1) const uint ANALYSIS = 0;
layout(constant_id = 2) const uint FALLBACK = 1;  // 0: no fp64 re-evaluation (to measure what it prevents)
layout(constant_id = 3) const uint BINNED = 0;    // 1: only the 8x8 tiles of a big box that the triangle can touch
layout(constant_id = 4) const uint METHOD2D = 0;  // 1: the paper's baseline, 2D homogeneous rasterization (2dr)
const bool R3D_FALLBACK = FALLBACK == 1;
const bool R3D_2D = METHOD2D == 1;
#include "raster3d.glsl.inc"
layout(local_size_x = 64) in;

layout(set = 0, binding = 0) uniform Constants { Raster3dConstants r3; };
layout(set = 0, binding = 1) readonly buffer Triangles { vec4 triVerts[]; };  // 3 per triangle, xyz world
layout(set = 0, binding = 2) buffer Visibility { uint64_t vis[]; };
layout(set = 0, binding = 3) buffer Items { uint itemCount; uint itemPad[3]; uvec2 items[]; };  // (id, tx | ty << 16)
layout(set = 0, binding = 4) buffer Counters { uint64_t counters[kR3dCounterCount]; };
layout(set = 0, binding = 5) buffer Coverage { uint coverage[]; };
layout(set = 0, binding = 6) buffer Tested { uint testedPerPixel[]; };  // ANALYSIS: pixel tests per pixel
// Binned: per screen tile [0, T) count, [T, 2T) first entry, [2T, 3T) fill cursor; then the list.
layout(set = 0, binding = 7) buffer Bins { uint bins[]; };
layout(set = 0, binding = 8) buffer BinList { uint binList[]; };

struct Tally {
  uint tested, fallbacks, covered, atomics;
};

// The key (t bits << 32 | id) of a covered pixel within [znear, zfar]; false if none.
bool pixelKey(uint id, R3dSetup s, uint x, uint y, inout Tally tally, out uint64_t key) {
  ++tally.tested;
  const uint pixel = y * r3.width + x;
  if (ANALYSIS == 1) atomicAdd(testedPerPixel[pixel], 1u);
  float t;
  key = ~0ul;
  if (!r3dCovers(s, float(x), float(y), r3, t, tally.fallbacks)) return false;
  if (ANALYSIS == 1) {
    atomicAdd(coverage[pixel], 1u);
    ++tally.covered;
  }
  if (!(t >= r3.depth.x && t <= r3.depth.y)) return false;  // the near and far planes clip (and NaN)
  key = (uint64_t(floatBitsToUint(t)) << 32) | uint64_t(id);
  return true;
}

void testPixel(uint id, R3dSetup s, uint x, uint y, inout Tally tally) {
  uint64_t key;
  if (!pixelKey(id, s, x, y, tally, key)) return;
  atomicMin(vis[y * r3.width + x], key);
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
  const vec3 w0 = triVerts[3u * id].xyz, w1 = triVerts[3u * id + 1u].xyz, w2 = triVerts[3u * id + 2u].xyz;
  if (!(R3D_2D ? r2dSetup(w0, w1, w2, r3, s) : r3dSetup(w0, w1, w2, r3, s))) return false;
  r3dScreenBox(s, r3, lo, hi);
  return hi.x >= lo.x && hi.y >= lo.y;
}

uint tilesX() { return (r3.width + 7u) / 8u; }
uint tileCount() { return tilesX() * ((r3.height + 7u) / 8u); }

// The screen tile (tx, ty) clipped to the box [lo, hi]: its first and last pixel.
void tileInBox(uint tx, uint ty, ivec2 lo, ivec2 hi, out uvec2 a, out ivec2 b) {
  a = uvec2(max(ivec2(tx * 8u, ty * 8u), lo));
  b = min(ivec2(tx * 8u + 7u, ty * 8u + 7u), hi);
}

void rasterizeBox(uint id, R3dSetup s, uvec2 a, ivec2 b, inout Tally tally) {
  for (uint y = a.y; y <= uint(b.y); ++y)
    for (uint x = a.x; x <= uint(b.x); ++x) testPixel(id, s, x, y, tally);
}

// Binned, PASS 0 (fill = false) and PASS 3 (fill = true): the screen tiles of a big box that the
// triangle can touch.
void binTriangle(uint id, R3dSetup s, ivec2 lo, ivec2 hi, bool fill, inout Tally tally) {
  const uint T = tileCount(), capacity = r3.itemCapacity;
  for (uint ty = uint(lo.y) / 8u; ty <= uint(hi.y) / 8u; ++ty)
    for (uint tx = uint(lo.x) / 8u; tx <= uint(hi.x) / 8u; ++tx) {
      uvec2 a;
      ivec2 b;
      tileInBox(tx, ty, lo, hi, a, b);
      if (!tileMayBeCovered(s, a.x, a.y, b)) continue;
      const uint tile = ty * tilesX() + tx;
      if (!fill) {
        atomicAdd(bins[tile], 1u);
        continue;
      }
      const uint entry = bins[T + tile] + atomicAdd(bins[2u * T + tile], 1u);
      if (entry < capacity) {
        binList[entry] = id;
      } else {  // the list is full: this thread rasterizes the tile (slower, never dropped)
        if (ANALYSIS == 1) atomicAdd(counters[kR3dCounterOverflow], 1ul);
        rasterizeBox(id, s, a, b, tally);
      }
    }
}

void perTriangle(bool fill) {
  const uint id = gl_GlobalInvocationID.x;
  if (id >= r3.triangleCount) return;
  R3dSetup s;
  ivec2 lo, hi;
  if (!setupTriangle(id, s, lo, hi)) return;
  const uint w = uint(hi.x - lo.x + 1), h = uint(hi.y - lo.y + 1);
  const bool big = w * h > r3.smallArea;
  if (ANALYSIS == 1 && !fill) {
    atomicAdd(counters[kR3dCounterSetups], 1ul);
    if (big) atomicAdd(counters[kR3dCounterBig], 1ul);
  }
  Tally tally = Tally(0u, 0u, 0u, 0u);
  if (BINNED == 1) {
    if (big)
      binTriangle(id, s, lo, hi, fill, tally);
    else if (!fill)
      rasterizeBox(id, s, uvec2(lo), hi, tally);
    flush(tally);
    return;
  }
  if (big) {
    const uint tw = (w + 7u) / 8u, th = (h + 7u) / 8u;
    const uint n = tw * th;
    const uint first = atomicAdd(itemCount, n);
    if (first + n <= r3.itemCapacity) {
      for (uint ty = 0u; ty < th; ++ty)
        for (uint tx = 0u; tx < tw; ++tx) items[first + ty * tw + tx] = uvec2(id, tx | (ty << 16));
      return;
    }
    if (ANALYSIS == 1) atomicAdd(counters[kR3dCounterOverflow], 1ul);
  }
  rasterizeBox(id, s, uvec2(lo), hi, tally);
  flush(tally);
}

// Brute force, PASS 1.
void perItem() {
  const uint count = min(itemCount, r3.itemCapacity);
  Tally tally = Tally(0u, 0u, 0u, 0u);
  for (uint item = gl_WorkGroupID.x; item < count; item += gl_NumWorkGroups.x) {
    const uvec2 it = items[item];
    R3dSetup s;
    ivec2 lo, hi;
    if (!setupTriangle(it.x, s, lo, hi)) continue;  // never: PASS 0 set it up the same way
    const uint x0 = uint(lo.x) + (it.y & 0xFFFFu) * 8u, y0 = uint(lo.y) + (it.y >> 16) * 8u;
    const uint x = x0 + gl_LocalInvocationID.x % 8u, y = y0 + gl_LocalInvocationID.x / 8u;
    if (x <= uint(hi.x) && y <= uint(hi.y)) testPixel(it.x, s, x, y, tally);
  }
  flush(tally);
}

// Binned, PASS 2: exclusive prefix sum of the per-tile counts (one workgroup of 64 threads, each a
// contiguous chunk), the cursors cleared, and the total entries counted (analysis).
shared uint sChunk[64];
void scanBins() {
  const uint T = tileCount(), i = gl_LocalInvocationID.x, chunk = (T + 63u) / 64u;
  const uint first = min(i * chunk, T), last = min(first + chunk, T);
  uint sum = 0u;
  for (uint k = first; k < last; ++k) sum += bins[k];
  sChunk[i] = sum;
  barrier();
  if (i == 0u) {
    uint run = 0u;
    for (uint k = 0u; k < 64u; ++k) {
      const uint c = sChunk[k];
      sChunk[k] = run;
      run += c;
    }
    if (ANALYSIS == 1) counters[kR3dCounterListEntries] = uint64_t(run);
  }
  barrier();
  uint run = sChunk[i];
  for (uint k = first; k < last; ++k) {
    bins[T + k] = run;
    bins[2u * T + k] = 0u;
    run += bins[k];
  }
}

// Binned, PASS 1: one workgroup per screen tile.
shared R3dSetup sSetup[64];
shared ivec4 sBox[64];  // lo, hi; empty (hi < lo) for a slot past the batch
shared uint sId[64];
void perScreenTile() {
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
    barrier();
    const uint n = min(64u, end - base);
    for (uint j = 0u; j < n; ++j) {
      const ivec4 b = sBox[j];
      if (int(x) < b.x || int(y) < b.y || int(x) > b.z || int(y) > b.w) continue;
      uint64_t key;
      if (pixelKey(sId[j], sSetup[j], x, y, tally, key)) best = min(best, key);
    }
    barrier();
  }
  if (best != ~0ul) {
    atomicMin(vis[y * r3.width + x], best);
    ++tally.atomics;
  }
  flush(tally);
}

void main() {
  if (PASS == 0)
    perTriangle(false);
  else if (PASS == 1 && BINNED == 1)
    perScreenTile();
  else if (PASS == 1)
    perItem();
  else if (PASS == 2)
    scanBins();
  else
    perTriangle(true);
}
