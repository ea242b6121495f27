#version 460
// Primary visibility by 3D rasterization (raster3d.glsl.inc) or by the paper's 2D homogeneous
// baseline (METHOD2D), brute force over each triangle's screen box ("3dr", "2dr") or binned into
// the screen's 8x8 tiles ("3dr-binned"). The per-triangle and per-work-item passes (this shader;
// only PASS 0 uses shared memory, 0.5 KB, so none loses occupancy to it):
//   PASS 0: one thread per triangle: setup and screen box; a box of at most smallArea pixels is
//           rasterized by the thread itself; a larger one takes work items in the list (brute
//           force: the 8x8 tiles of its box; binned: the screen's 8x8 tiles the box overlaps) and
//           writes one span (its id and first item). The workgroup takes its items and spans with
//           one atomic. The passes after it expand the items from the spans, a thread (binned) or
//           a run of items a workgroup (brute force), spread over the GPU: a workgroup writing its
//           own big triangles' items made the pass wait on the few whose triangles cover much of
//           the screen (docs/methods/3d-rasterization.md).
//           When the list is full the thread rasterizes its box itself: slower, never a dropped
//           pixel (counted), and its span marks the slots it took empty (kNoItem). Which
//           triangles find it full depends on the order of the atomics, so the items every big
//           triangle asks for are summed too (itemDemand; the next pass keeps the most of any
//           plane), and the host grows the list to that and renders the frame again
//           (Raster3dPass::growList): the frames a run keeps find it full nowhere, on every run.
//   PASS 1: brute force: tileWorkgroups workgroups of 64 threads, each over a run of consecutive
//           work items, one pixel a thread, one atomicMin per covered pixel.
//   Binned, count-scan-fill over the work items, a thread per item:
//   PASS 0 also keeps each big triangle's setup at its span's index (setups, R3dSetupRecord):
//           the passes after it read it back instead of setting the triangle up for every tile.
//   PASS 3: count: finds each item's triangle and tile (its span), keeps the item if the
//           triangle can touch the tile (tileMayBeCovered: its edge functions at the tile's
//           corners), counts +1 on the tile and writes the item for the fill.
//   (raster3d_scan.comp.glsl: each tile's first list entry.)
//   PASS 4: fill: each kept item's span at its tile's offset + atomicAdd(cursor).
//   (raster3d_tiles.comp.glsl: one workgroup per screen tile rasterizes its list.)
// A covered pixel within [znear, zfar] takes atomicMin of (t bits << 32 | triangle id): the nearest
// hit, ties to the smaller id, the same on every run and for every order of work (t > 0, and
// positive floats order like their bits), so binned equals brute force bit for bit.
// ANALYSIS = 1 also counts (kR3dCounter*) and adds coverage per pixel (depth-test free).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared/gpu_types.h"

#define R3D_SAMPLE_PLANES
#include "raster3d_common.glsl.inc"
layout(local_size_x = 64) in;

// PASS 0: what each thread's triangle asks of the list, and the workgroup's prefix sums over them
// (inclusive, in thread order, so that a workgroup's spans are in the order of its items).
shared uint sItems[64];
shared uint sSpans[64];
shared uvec2 sBase;  // where the workgroup's items and spans start

void perTriangle() {
  const uint lid = gl_LocalInvocationID.x;
  const uint id = gl_GlobalInvocationID.x;
  R3dSetup s;
  ivec2 lo, hi;
  // Every thread reaches the barriers: no early return.
  bool own = id < r3.triangleCount && setupTriangle(id, s, lo, hi);  // rasterized by this thread
  Tally tally = Tally(0u, 0u, 0u, 0u);
  uint n = 0u;  // the items a big triangle asks for
  if (own) {
    const uint w = uint(hi.x - lo.x + 1), h = uint(hi.y - lo.y + 1);
    const bool big = R3D_SHARED || w * h > r3.smallArea;  // shared planes: all binned
    if (ANALYSIS == 1) {
      atomicAdd(counters[kR3dCounterSetups], 1ul);
      if (big) atomicAdd(counters[kR3dCounterBig], 1ul);
    }
    // Brute force: the 8x8 tiles of the box; binned: the screen tiles the box overlaps.
    if (big) n = BINNED == 1 ? (uint(hi.x) / 8u - uint(lo.x) / 8u + 1u) * (uint(hi.y) / 8u - uint(lo.y) / 8u + 1u)
                             : ((w + 7u) / 8u) * ((h + 7u) / 8u);
  }
  sItems[lid] = n;
  sSpans[lid] = n > 0u ? 1u : 0u;
  barrier();
  for (uint d = 1u; d < 64u; d <<= 1u) {
    const uvec2 add = lid >= d ? uvec2(sItems[lid - d], sSpans[lid - d]) : uvec2(0u);
    barrier();
    sItems[lid] += add.x;
    sSpans[lid] += add.y;
    barrier();
  }
  // One 64-bit atomic a workgroup takes its items and its spans together (tens of thousands of
  // atomics on one address serialize in the L2). Once the list is full (a read that may be stale:
  // then the atomicAdd decides) nothing is taken; this also keeps the item count far from wrapping
  // around 2^32.
  const uint items = sItems[63], spanTotal = sSpans[63];
  if (lid == 0u) {
    sBase = uvec2(r3.itemCapacity, kNoItem);  // nothing taken
    if (items > 0u) {
      atomicAdd(itemDemand, uint64_t(items));
      if (itemCount() < r3.itemCapacity) {
        const uint64_t was = atomicAdd(itemsAndSpans, (uint64_t(spanTotal) << 32) | uint64_t(items));
        sBase = uvec2(uint(was & 0xFFFFFFFFul), uint(was >> 32));
      }
    }
  }
  barrier();
  const uvec2 base = sBase;
  if (n > 0u) {
    // A span for every big triangle once the workgroup took its slots (a slot the passes after it
    // read must belong to a written span: one of an earlier frame would be another triangle's).
    const uint first = base.x + sItems[lid] - n;
    const bool fits = base.x < r3.itemCapacity && first + n <= r3.itemCapacity;
    if (base.y != kNoItem) {
      const uint k = base.y + sSpans[lid] - 1u;
      spans[k] = uvec2(fits ? id : kNoItem, first);
      // Binned: the setup, once, for the passes after this one (a span of kNoItem has none).
      if (BINNED == 1 && fits) storeSetupRecord(k, id, s, lo, hi);
    }
    if (fits) {
      own = false;
    } else {
      // The list is full: this thread rasterizes its box (slower, never a dropped pixel; counted).
      // Its span (id kNoItem) covers the slots it took, up to the end of the list: no pass reads
      // them as items. Spans after it, of this workgroup or a later one, start at or past the end.
      if (ANALYSIS == 1) atomicAdd(counters[kR3dCounterOverflow], 1ul);
    }
  }
  if (own && R3D_SHARED)
    rasterizeBoxPlanes(id, s, uvec2(lo), hi);
  else if (own)
    rasterizeBox(id, s, uvec2(lo), hi, tally);
  flush(tally);
}

// Brute force, PASS 1.
// PASS 1 and PASS 3, the first after PASS 0: the most items a plane of the frame asked for.
void keepDemand() {
  if (gl_GlobalInvocationID.x == 0u) atomicMax(itemDemandMax, itemDemand);
}

void perItem() {
  keepDemand();
  // Each workgroup walks a run of consecutive items, a pixel a thread: a triangle's items are
  // consecutive, so the workgroup finds its span and sets it up once for all of them.
  const uint count = min(itemCount(), r3.itemCapacity);
  const uint per = (count + gl_NumWorkGroups.x - 1u) / gl_NumWorkGroups.x;
  const uint begin = gl_WorkGroupID.x * per, end = min(begin + per, count);
  Tally tally = Tally(0u, 0u, 0u, 0u);
  uint spanEnd = begin, id = kNoItem, first = 0u, tilesWide = 1u;
  R3dSetup s;
  ivec2 lo = ivec2(0), hi = ivec2(-1);
  for (uint item = begin; item < end; ++item) {
    if (item >= spanEnd) {  // the next span (uniform across the workgroup)
      const uint k = findSpan(item);
      spanEnd = k + 1u < spanCount() ? spans[k + 1u].y : count;
      id = spans[k].x;
      first = spans[k].y;
      // (setupTriangle never fails here: PASS 0 set the triangle up the same way.)
      if (id == kNoItem || !setupTriangle(id, s, lo, hi)) {
        item = spanEnd - 1u;  // a triangle that found the list full: its slots hold nothing
        continue;
      }
      tilesWide = uint(hi.x - lo.x) / 8u + 1u;
    }
    const uint index = item - first, ty = index / tilesWide, tx = index - ty * tilesWide;
    const uint x = uint(lo.x) + tx * 8u + gl_LocalInvocationID.x % 8u;
    const uint y = uint(lo.y) + ty * 8u + gl_LocalInvocationID.x / 8u;
    if (x <= uint(hi.x) && y <= uint(hi.y)) testPixel(id, s, x, y, tally);
  }
  flush(tally);
}

// Binned, PASS 3 (count): a thread per work item, 64 consecutive items a workgroup at a time, each
// found in its span and written for the fill: (id, screen tile | kKept) when the triangle can touch
// the tile. The workgroup finds the span of its first item by a 64-way search (each of its 64
// threads probes one point a step: 3 steps for 262k spans, where a binary search waits on 18
// dependent loads), then the first items of the 64 spans from there (64 consecutive items lie in
// at most 64 spans) go to shared memory, where each thread finds its own.
shared uint sSpanLo, sSpanHi, sProbes;
shared uint sFirst[64];

void countItems() {
  keepDemand();
  const uint count = min(itemCount(), r3.itemCapacity), spanTotal = spanCount(), lid = gl_LocalInvocationID.x;
  const uint stride = gl_NumWorkGroups.x * 64u;
  for (uint chunk = gl_WorkGroupID.x * 64u; chunk < count; chunk += stride) {
    if (lid == 0u) {
      sSpanLo = 0u;
      sSpanHi = spanTotal;
    }
    barrier();
    // Invariant: span sSpanLo starts at or before `chunk`, span sSpanHi (if any) after it.
    while (sSpanHi - sSpanLo > 1u) {  // uniform: every thread reads the same words
      const uint lo = sSpanLo, hi = sSpanHi, step = (hi - lo + 63u) / 64u;
      const uint probe = lo + lid * step;
      if (lid == 0u) sProbes = 0u;
      barrier();
      if (probe < hi && spans[probe].y <= chunk) atomicAdd(sProbes, 1u);  // the true probes are a prefix
      barrier();
      if (lid == 0u) {
        sSpanLo = lo + (sProbes - 1u) * step;
        sSpanHi = min(sSpanLo + step, hi);
      }
      barrier();
    }
    const uint base = sSpanLo;
    sFirst[lid] = base + lid < spanTotal ? spans[base + lid].y : 0xFFFFFFFFu;
    barrier();
    const uint item = chunk + lid;
    if (item < count) {
      uint k = 0u;  // the last of sFirst at or before item (sFirst[0] is)
      for (uint w = 32u; w > 0u; w >>= 1u)
        if (sFirst[k + w] <= item) k += w;
      const uvec2 span = spans[base + k];
      if (span.x == kNoItem) {
        items[item] = uvec2(kNoItem, 0u);
      } else {
        ivec2 lo, hi;
        R3dSetup s = loadSetupRecord(base + k, lo, hi);  // PASS 0's setup
        if (R3D_SHARED) {  // binned for every plane: the largest rowA and errA (raster3d_common.glsl.inc)
          vec3 aMin;
          loadPlaneExtents(base + k, aMin, s.rowA, s.errA);
        }
        const uint index = item - span.y, tilesWide = uint(hi.x) / 8u - uint(lo.x) / 8u + 1u;
        const uint ty = index / tilesWide, tx = index - ty * tilesWide;
        const uint tile = (uint(lo.y) / 8u + ty) * tilesX() + uint(lo.x) / 8u + tx;
        uvec2 a;
        ivec2 b;
        tileInBox(tile % tilesX(), tile / tilesX(), lo, hi, a, b);
        const bool kept = tileMayBeCovered(s, a.x, a.y, b);
        if (kept) atomicAdd(bins[tile], 1u);
        items[item] = uvec2(base + k, kept ? tile | kKept : tile);  // the span: its setup and id
      }
    }
    barrier();  // the shared words are the next chunk's
  }
}

// Binned, PASS 4 (fill): a thread per kept item, striding: its triangle id at its tile's offset.
void fillItems() {
  const uint count = min(itemCount(), r3.itemCapacity), T = tileCount();
  const uint stride = gl_NumWorkGroups.x * 64u;
  Tally tally = Tally(0u, 0u, 0u, 0u);
  for (uint item = gl_GlobalInvocationID.x; item < count; item += stride) {
    const uvec2 it = items[item];
    if (it.x == kNoItem || (it.y & kKept) == 0u) continue;
    const uint tile = it.y & ~kKept;
    const uint entry = bins[T + tile] + atomicAdd(bins[2u * T + tile], 1u);
    if (entry < r3.itemCapacity) {
      binList[entry] = it.x;  // the span, whose setup the tile pass reads
      continue;
    }
    // The list is full: this thread rasterizes the tile (slower, never dropped; counted).
    if (ANALYSIS == 1) atomicAdd(counters[kR3dCounterOverflow], 1ul);
    ivec2 lo, hi;
    const R3dSetup s = loadSetupRecord(it.x, lo, hi);
    uvec2 a;
    ivec2 b;
    tileInBox(tile % tilesX(), tile / tilesX(), lo, hi, a, b);
    if (R3D_SHARED)
      rasterizeBoxPlanes(setups[it.x].info.x, s, a, b);
    else
      rasterizeBox(setups[it.x].info.x, s, a, b, tally);
  }
  flush(tally);
}

void main() {
  if (PASS == 0)
    perTriangle();
  else if (PASS == 1)
    perItem();
  else if (PASS == 3)
    countItems();
  else
    fillItems();
}
