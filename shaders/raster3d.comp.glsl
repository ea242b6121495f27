#version 460
// Primary visibility by 3D rasterization (raster3d.glsl.inc) or by the paper's 2D homogeneous
// baseline (METHOD2D), brute force over each triangle's screen box ("3dr", "2dr") or binned into
// the screen's 8x8 tiles ("3dr-binned"). The per-triangle and per-work-item passes (this shader;
// only PASS 0 uses shared memory, 1.5 KB, so none loses occupancy to it):
//   PASS 0: one thread per triangle: setup and screen box; a box of at most smallArea pixels is
//           rasterized by the thread itself; a larger one is appended as work items (one
//           atomicAdd per triangle): brute force, the 8x8 tiles of its box; binned, the screen's
//           8x8 tiles the box overlaps. The workgroup's 64 threads write those items together.
//           When the list is full the thread rasterizes its box itself: slower, never a dropped
//           pixel (counted), and marks the slots it took empty (kNoItem). Which triangles find it
//           full depends on the order of the atomics, so the items every big triangle asks for
//           are summed too (itemDemand; the next pass keeps the most of any plane), and the host
//           grows the list to that and renders the frame again (Raster3dPass::growList): the
//           frames a run keeps find it full nowhere, on every run.
//   PASS 1: brute force: tileWorkgroups workgroups of 64 threads stride over the work items, one
//           pixel each, one atomicMin per covered pixel.
//   Binned, count-scan-fill over the work items, a thread per item:
//   PASS 3: count: keeps an item if the triangle can touch its tile (tileMayBeCovered: its edge
//           functions at the tile's corners) and counts +1 on the tile.
//   (raster3d_scan.comp.glsl: each tile's first list entry.)
//   PASS 4: fill: each kept item's triangle id at its tile's offset + atomicAdd(cursor).
//   (raster3d_tiles.comp.glsl: one workgroup per screen tile rasterizes its list.)
// A covered pixel within [znear, zfar] takes atomicMin of (t bits << 32 | triangle id): the nearest
// hit, ties to the smaller id, the same on every run and for every order of work (t > 0, and
// positive floats order like their bits), so binned equals brute force bit for bit.
// ANALYSIS = 1 also counts (kR3dCounter*) and adds coverage per pixel (depth-test free).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared/gpu_types.h"

#include "raster3d_common.glsl.inc"
layout(local_size_x = 64) in;

// PASS 0's big triangles of this workgroup, whose items all 64 threads write together: one thread
// writing a big box's items alone took up to the whole pass (a triangle across half the screen
// has about 16,000), 0.28 ms in brute force and 0.61 ms binned on the atrium at 1080p on an H200
// whatever the thread box (results/h200/continuum-32/pass0).
shared uint sBigId[64];
shared uint sBigFirst[64];
shared uvec4 sBigSpan[64];  // first tile x, first tile y, tiles a row, items
shared uint sBigCount;
shared uint sDemand;  // the items this workgroup's big triangles ask for

void perTriangle() {
  const uint lid = gl_LocalInvocationID.x;
  if (lid == 0u) {
    sBigCount = 0u;
    sDemand = 0u;
  }
  barrier();
  const uint id = gl_GlobalInvocationID.x;
  R3dSetup s;
  ivec2 lo, hi;
  // Every thread reaches both barriers: no early return.
  bool own = id < r3.triangleCount && setupTriangle(id, s, lo, hi);  // rasterized by this thread
  Tally tally = Tally(0u, 0u, 0u, 0u);
  if (own) {
    const uint w = uint(hi.x - lo.x + 1), h = uint(hi.y - lo.y + 1);
    const bool big = w * h > r3.smallArea;
    if (ANALYSIS == 1) {
      atomicAdd(counters[kR3dCounterSetups], 1ul);
      if (big) atomicAdd(counters[kR3dCounterBig], 1ul);
    }
    if (big) {
      // Brute force: the 8x8 tiles of the box; binned: the screen tiles the box overlaps.
      const uvec2 t0 = BINNED == 1 ? uvec2(lo) / 8u : uvec2(0u);
      const uvec2 t1 = BINNED == 1 ? uvec2(hi) / 8u : uvec2(w - 1u, h - 1u) / 8u;
      const uint tw = t1.x - t0.x + 1u, th = t1.y - t0.y + 1u;
      const uint n = tw * th;
      atomicAdd(sDemand, n);
      // Once the list is full (a read that may be stale: then the atomicAdd below decides), no slot
      // is taken; this also keeps itemCount far from wrapping around 2^32.
      const uint first = itemCount >= r3.itemCapacity ? r3.itemCapacity : atomicAdd(itemCount, n);
      if (first + n <= r3.itemCapacity) {
        const uint k = atomicAdd(sBigCount, 1u);
        sBigId[k] = id;
        sBigFirst[k] = first;
        sBigSpan[k] = uvec4(t0, tw, n);
        own = false;
      } else {
        // The slots of the list this thread took but cannot fill are marked empty: the passes
        // after it read the list up to min(itemCount, itemCapacity), and a slot left unwritten
        // would hold a previous frame's item (a pair tested twice: coverage counted twice, or in
        // binned mode a kept item filled into a tile whose count did not include it, overwriting
        // another tile's entries). Then this thread rasterizes its box.
        for (uint i = first; i < min(first + n, r3.itemCapacity); ++i) items[i] = uvec2(kNoItem, 0u);
        if (ANALYSIS == 1) atomicAdd(counters[kR3dCounterOverflow], 1ul);
      }
    }
  }
  barrier();
  if (lid == 0u && sDemand > 0u) atomicAdd(itemDemand, uint64_t(sDemand));
  const uint bigCount = sBigCount;
  for (uint b = 0u; b < bigCount; ++b) {
    const uvec4 span = sBigSpan[b];
    const uint bid = sBigId[b], first = sBigFirst[b];
    for (uint i = lid; i < span.w; i += 64u) {
      const uint ty = i / span.z, tx = i - ty * span.z;
      items[first + i] = BINNED == 1 ? uvec2(bid, (span.y + ty) * tilesX() + span.x + tx) : uvec2(bid, tx | (ty << 16));
    }
  }
  if (own) rasterizeBox(id, s, uvec2(lo), hi, tally);
  flush(tally);
}

// Brute force, PASS 1.
// PASS 1 and PASS 3, the first after PASS 0: the most items a plane of the frame asked for.
void keepDemand() {
  if (gl_GlobalInvocationID.x == 0u) atomicMax(itemDemandMax, itemDemand);
}

void perItem() {
  keepDemand();
  const uint count = min(itemCount, r3.itemCapacity);
  Tally tally = Tally(0u, 0u, 0u, 0u);
  for (uint item = gl_WorkGroupID.x; item < count; item += gl_NumWorkGroups.x) {
    const uvec2 it = items[item];
    if (it.x == kNoItem) continue;  // a slot of a triangle that found the list full
    R3dSetup s;
    ivec2 lo, hi;
    if (!setupTriangle(it.x, s, lo, hi)) continue;  // never: PASS 0 set it up the same way
    const uint x0 = uint(lo.x) + (it.y & 0xFFFFu) * 8u, y0 = uint(lo.y) + (it.y >> 16) * 8u;
    const uint x = x0 + gl_LocalInvocationID.x % 8u, y = y0 + gl_LocalInvocationID.x / 8u;
    if (x <= uint(hi.x) && y <= uint(hi.y)) testPixel(it.x, s, x, y, tally);
  }
  flush(tally);
}

// Binned, PASS 3 (count) and PASS 4 (fill): a thread per work item, striding.
void binItems(bool fill) {
  if (!fill) keepDemand();
  const uint count = min(itemCount, r3.itemCapacity), T = tileCount();
  const uint stride = gl_NumWorkGroups.x * 64u;
  Tally tally = Tally(0u, 0u, 0u, 0u);
  for (uint item = gl_GlobalInvocationID.x; item < count; item += stride) {
    const uvec2 it = items[item];
    if (it.x == kNoItem) continue;  // a slot of a triangle that found the list full
    const uint tile = it.y & ~kKept;
    if (!fill) {
      R3dSetup s;
      ivec2 lo, hi;
      if (!setupTriangle(it.x, s, lo, hi)) continue;  // never: PASS 0 set it up the same way
      uvec2 a;
      ivec2 b;
      tileInBox(tile % tilesX(), tile / tilesX(), lo, hi, a, b);
      if (!tileMayBeCovered(s, a.x, a.y, b)) continue;
      atomicAdd(bins[tile], 1u);
      items[item].y = it.y | kKept;
      continue;
    }
    if ((it.y & kKept) == 0u) continue;
    const uint entry = bins[T + tile] + atomicAdd(bins[2u * T + tile], 1u);
    if (entry < r3.itemCapacity) {
      binList[entry] = it.x;
      continue;
    }
    // The list is full: this thread rasterizes the tile (slower, never dropped; counted).
    if (ANALYSIS == 1) atomicAdd(counters[kR3dCounterOverflow], 1ul);
    R3dSetup s;
    ivec2 lo, hi;
    if (!setupTriangle(it.x, s, lo, hi)) continue;
    uvec2 a;
    ivec2 b;
    tileInBox(tile % tilesX(), tile / tilesX(), lo, hi, a, b);
    rasterizeBox(it.x, s, a, b, tally);
  }
  flush(tally);
}

void main() {
  if (PASS == 0)
    perTriangle();
  else if (PASS == 1)
    perItem();
  else
    binItems(PASS == 4);
}
