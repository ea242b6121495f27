#version 460
// The compute splat's binning (splat=compute; effects/indirect/indirect_pass.cpp recordSplatInto),
// the steps picked by MODE (the count and fill in two forms), 256 threads a group:
//  MODE 0 (boxes)  a thread a slot: the pixel box of its footprint's quad x ± du/2 ± dv/2 (the raster
//                  splat's, photon_splat.vert.glsl), one pixel wider on each side, clamped to the
//                  image, and the same box in coarse bins of sc.binPixels; empty for a slot
//                  that holds no stored photon or whose quad lies outside the image. A quad with a
//                  corner behind the eye (w <= 0) takes the whole image.
//  MODE 1 (count)  a group per (chunk, sc.rowBins bins of a row): the slots of the chunk whose
//                  coarse box holds each bin (each box read once for the row's bins).
//  MODE 2 (scan)   one group: the counts' exclusive prefix, bin after bin and chunk after chunk, so
//                  bin b's slots are entries [start_b, start_b + count_b) of the list, in slot
//                  order; a bin whose entries would pass the list's capacity is marked, and the
//                  gather scans every slot for it instead (slower, the same sum).
//  MODE 3 (fill)   a group per (chunk, sc.rowBins bins of a row): each bin's overlapping slots of
//                  the chunk written in slot order (per bin, a subgroup ballot's prefix), so every
//                  entry's position is fixed: deterministic.
//  MODE 4, 5       the count and the fill with sc.rowBins = 1: a single bin's loops.
// The slot a thread takes in a round is ordered by (gl_SubgroupID, gl_SubgroupInvocationID), so the
// list's order is the slots' whatever the hardware's mapping of local indices to subgroups.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_control_flow_attributes : require
#include "shared/gpu_types.h"
layout(local_size_x = 256) in;
layout(constant_id = 0) const uint MODE = 0u;
// Each step declares only the shared memory it uses: the arrays are sized by MODE (1 entry where
// unused). Declared for every step, they took the boxes step (MODE 0) from 2,052 to 6,180 B of
// shared memory, and it ran 5-6 % slower on the H200 with unchanged code (results/h200/raster3d-52).
#define HB_SPLAT_APPEND_SLOTS (MODE == 5u ? 256u : 1u)
#include "splat_append.glsl.inc"

uniform Frame { FrameConstants frame; };
readonly buffer Photons { Photon photons[]; };
buffer Boxes { uvec2 boxes[]; };
buffer Coarse { uint coarse[]; };
buffer Counts { uint counts[]; };
buffer Bins { uvec4 bins[]; };
buffer List { uint list[]; };
layout(push_constant) uniform Push { SplatConstants sc; };

const uvec2 kEmptyBox = uvec2(0xFFFFFFFFu, 0u);
const uint kEmptyCoarse = 0x000000FFu;  // x0 = 255 > x1 = 0: holds no bin

shared uint sCount;
shared uint sRunTotals[MODE == 2u ? 256u : 1u];          // scanCounts: each thread's run of counts, then its prefix
shared uint sRowCounts[MODE == 1u ? kSplatBinRow : 1u];  // countChunk: the row's bins' counts
shared uvec4 sRowTotals[MODE == 3u ? 256u : 1u];         // fillChunk: per subgroup, the row's bins' counts, 16 bits each

// The slot a thread takes in round `round` of its group's chunk (see the header), counted from the
// run's first slot (sc.first: a run splats slots [first, first + slots)).
uint slotOf(uint round) {
  return sc.first + gl_WorkGroupID.x * kSplatChunk + round * 256u + gl_SubgroupID * gl_SubgroupSize +
         gl_SubgroupInvocationID;
}
bool inRun(uint s) { return s - sc.first < sc.slots; }

void writeBoxes() {
  const uint k = sc.first + (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 256u + gl_LocalInvocationIndex;
  if (!inRun(k)) return;
  const Photon p = photons[k];
  if (floatBitsToUint(p.normalStatus.w) != kPhotonStored) {
    boxes[k] = kEmptyBox;
    coarse[k] = kEmptyCoarse;
    return;
  }
  const ivec2 extent = ivec2(frame.extent.xy);
  vec2 lo = vec2(1e30), hi = vec2(-1e30);
  bool behind = false;
  for (uint c = 0u; c < 4u; ++c) {
    const vec2 corner = vec2((c == 1u || c == 2u) ? 0.5 : -0.5, c >= 2u ? 0.5 : -0.5);
    const vec4 clip =
        frame.viewProj * vec4(p.positionFluxR.xyz + corner.x * p.duFluxG.xyz + corner.y * p.dvFluxB.xyz, 1.0);
    if (!(clip.w > 0.0)) behind = true;
    const vec2 px = (clip.xy / clip.w * 0.5 + 0.5) * frame.extent.xy;
    lo = min(lo, px);
    hi = max(hi, px);
  }
  ivec2 a = ivec2(0), b = extent - 1;
  if (!behind) {
    // Pixels whose centre i + 0.5 lies in [lo, hi], one more on each side for the raster's snapping.
    a = max(ivec2(ceil(clamp(lo, vec2(-2.0), vec2(extent + 2)) - 0.5)) - 1, ivec2(0));
    b = min(ivec2(floor(clamp(hi, vec2(-2.0), vec2(extent + 2)) - 0.5)) + 1, extent - 1);
  }
  if (any(greaterThan(a, b))) {
    boxes[k] = kEmptyBox;
    coarse[k] = kEmptyCoarse;
    return;
  }
  boxes[k] = uvec2(uint(a.x) | uint(a.y) << 16, uint(b.x) | uint(b.y) << 16);
  const uvec2 ca = uvec2(a) / sc.binPixels, cb = uvec2(b) / sc.binPixels;
  coarse[k] = ca.x | ca.y << 8 | cb.x << 16 | cb.y << 24;
}

// The bins a count or fill group takes (gl_WorkGroupID.y): sc.rowBins (at most kSplatBinRow)
// consecutive bins of one row, from bin (x0, y); the row's last group may hold fewer (valid: how
// many). The loops over a row's bins run to kSplatBinRow, unrolled, and skip bins past `valid`.
struct BinRow {
  uint x0, y, valid;
};
BinRow binRowOf() {
  const uint groupsX = (sc.binsX + sc.rowBins - 1u) / sc.rowBins;
  const uint x0 = (gl_WorkGroupID.y % groupsX) * sc.rowBins;
  return BinRow(x0, gl_WorkGroupID.y / groupsX, min(sc.rowBins, sc.binsX - x0));
}

// The bins of `row` that coarse box `box` holds: bit g for bin x0 + g (its x range ∩ the row's).
uint rowMask(uint box, BinRow row) {
  const uvec4 b = uvec4(box & 0xFFu, (box >> 8) & 0xFFu, (box >> 16) & 0xFFu, box >> 24);
  if (row.y < b.y || row.y > b.w) return 0u;
  const uint lo = max(b.x, row.x0), hi = min(b.z, row.x0 + row.valid - 1u);
  return lo > hi ? 0u : (2u << (hi - row.x0)) - (1u << (lo - row.x0));
}

// Whether coarse box `box` holds bin (x, y): the single-bin steps' test (MODE 4, 5), four compares
// where rowMask builds a row's mask.
bool coarseHolds(uint box, uint x, uint y) {
  const uvec4 b = uvec4(box & 0xFFu, (box >> 8) & 0xFFu, (box >> 16) & 0xFFu, box >> 24);
  return x >= b.x && x <= b.z && y >= b.y && y <= b.w;
}

void countChunk() {
  const BinRow row = binRowOf();
  if (gl_LocalInvocationIndex < kSplatBinRow) sRowCounts[gl_LocalInvocationIndex] = 0u;
  barrier();
  // Each slot's coarse box is read once for the row's bins; a thread's count of a bin is at most
  // the chunk's rounds (256), so two bins share a uint in 16-bit halves.
  uvec4 n = uvec4(0u);
  for (uint round = 0u; round < kSplatChunk / 256u; ++round) {
    const uint s = slotOf(round);
    if (!inRun(s)) continue;
    const uint m = rowMask(coarse[s], row);
    n += uvec4(m & 1u, (m >> 2) & 1u, (m >> 4) & 1u, (m >> 6) & 1u) |
         (uvec4((m >> 1) & 1u, (m >> 3) & 1u, (m >> 5) & 1u, (m >> 7) & 1u) << 16);
  }
  [[unroll]] for (uint g = 0u; g < kSplatBinRow; ++g) {  // a bin past the row counts 0
    const uint c = subgroupAdd((n[g >> 1] >> (16u * (g & 1u))) & 0xFFFFu);
    if (subgroupElect() && c != 0u) atomicAdd(sRowCounts[g], c);
  }
  barrier();
  const uint g = gl_LocalInvocationIndex;
  if (g < row.valid) counts[(row.y * sc.binsX + row.x0 + g) * sc.chunks + gl_WorkGroupID.x] = sRowCounts[g];
}

// One group: each thread takes a contiguous run of the (bin, chunk) counts, the runs' totals are
// prefixed in shared memory, and each run written back as starts. Then each bin's range and fit.
void scanCounts() {
  const uint total = sc.binsX * sc.binsY * sc.chunks, per = (total + 255u) / 256u;
  const uint first = gl_LocalInvocationIndex * per, last = min(first + per, total);
  uint run = 0u;
  for (uint i = first; i < last; ++i) run += counts[i];
  sRunTotals[gl_LocalInvocationIndex] = run;
  barrier();
  if (gl_LocalInvocationIndex == 0u) {
    uint acc = 0u;
    for (uint t = 0u; t < 256u; ++t) {
      const uint v = sRunTotals[t];
      sRunTotals[t] = acc;
      acc += v;
    }
    sCount = acc;  // every entry
  }
  barrier();
  uint acc = sRunTotals[gl_LocalInvocationIndex];
  for (uint i = first; i < last; ++i) {
    const uint v = counts[i];
    counts[i] = acc;
    acc += v;
  }
  memoryBarrierBuffer();
  barrier();
  const uint binCount = sc.binsX * sc.binsY;
  for (uint b = gl_LocalInvocationIndex; b < binCount; b += 256u) {
    const uint start = counts[b * sc.chunks];
    const uint end = b + 1u < binCount ? counts[(b + 1u) * sc.chunks] : sCount;
    bins[b] = uvec4(start, end - start, end <= sc.capacity ? 1u : 0u, 0u);
  }
}

// Each of the row's bins gets the chunk's slots that its coarse box holds, in slot order, at the
// entries the scan gave the (bin, chunk): per round, each subgroup's ballot per bin, the subgroups'
// counts through shared memory (two bins a uint, 16 bits each: at most 256 a round), a thread's
// place the counts before its subgroup plus its rank within the ballot. The list is the one a group
// per (bin, chunk) would write. The group stops once every bin has its (bin, chunk) entries.
void fillChunk() {
  const BinRow row = binRowOf();
  uint at[kSplatBinRow], end[kSplatBinRow];
  uint pending = 0u;  // the row's bins still to fill: uniform over the group
  [[unroll]] for (uint g = 0u; g < kSplatBinRow; ++g) {
    at[g] = end[g] = 0u;
    const uint b = row.y * sc.binsX + row.x0 + g;
    // A bin past the capacity is left out: the gather scans every slot for it.
    if (g < row.valid && bins[b].z != 0u) {
      at[g] = counts[b * sc.chunks + gl_WorkGroupID.x];
      end[g] = gl_WorkGroupID.x + 1u < sc.chunks ? counts[b * sc.chunks + gl_WorkGroupID.x + 1u]
                                                 : bins[b].x + bins[b].y;
      if (at[g] < end[g]) pending |= 1u << g;
    }
  }
  for (uint round = 0u; round < kSplatChunk / 256u && pending != 0u; ++round) {
    const uint s = slotOf(round);
    const uint m = inRun(s) ? rowMask(coarse[s], row) & pending : 0u;
    uint rank[kSplatBinRow];
    uvec4 mine = uvec4(0u);
    // Unrolled, without break or continue, so that rank[], at[] and end[] can stay in registers (a
    // build with break and continue in these loops ran the fill 2x slower on the H200); the bins
    // done or past the row (uniform) skip their ballot.
    [[unroll]] for (uint g = 0u; g < kSplatBinRow; ++g) {
      rank[g] = 0u;
      if (((pending >> g) & 1u) != 0u) {
        const uvec4 ballot = subgroupBallot(((m >> g) & 1u) != 0u);
        rank[g] = subgroupBallotExclusiveBitCount(ballot);
        mine[g >> 1] |= subgroupBallotBitCount(ballot) << (16u * (g & 1u));
      }
    }
    if (subgroupElect()) sRowTotals[gl_SubgroupID] = mine;
    barrier();
    uvec4 before = uvec4(0u), total = uvec4(0u);
    for (uint sg = 0u; sg < gl_NumSubgroups; ++sg) {
      const uvec4 v = sRowTotals[sg];
      before += sg < gl_SubgroupID ? v : uvec4(0u);
      total += v;
    }
    [[unroll]] for (uint g = 0u; g < kSplatBinRow; ++g) {  // a bin past the row or done adds 0
      const uint shift = 16u * (g & 1u);
      if (((m >> g) & 1u) != 0u) list[at[g] + ((before[g >> 1] >> shift) & 0xFFFFu) + rank[g]] = s;
      at[g] += (total[g >> 1] >> shift) & 0xFFFFu;
      if (at[g] >= end[g]) pending &= ~(1u << g);
    }
    barrier();
  }
}

// sc.rowBins = 1 (a run of few chunks): a group per (chunk, bin) with a single bin's loop, the
// count's and fill's code before the rows of bins (MODE 4, 5). The rows' code at one bin a group ran
// the fill of the first bounce's run at a stride 2.8x slower on the H200.
void countBin() {
  const BinRow row = binRowOf();
  if (gl_LocalInvocationIndex == 0u) sCount = 0u;
  barrier();
  uint n = 0u;
  for (uint round = 0u; round < kSplatChunk / 256u; ++round) {
    const uint s = slotOf(round);
    if (inRun(s) && coarseHolds(coarse[s], row.x0, row.y)) ++n;
  }
  n = subgroupAdd(n);
  if (subgroupElect()) atomicAdd(sCount, n);
  barrier();
  if (gl_LocalInvocationIndex == 0u) counts[(row.y * sc.binsX + row.x0) * sc.chunks + gl_WorkGroupID.x] = sCount;
}

void fillBin() {
  const BinRow row = binRowOf();
  const uint b = row.y * sc.binsX + row.x0;
  if (bins[b].z == 0u) return;  // past the capacity: the gather scans every slot for this bin
  uint at = counts[b * sc.chunks + gl_WorkGroupID.x];
  for (uint round = 0u; round < kSplatChunk / 256u; ++round) {
    const uint s = slotOf(round);
    const bool hit = inRun(s) && coarseHolds(coarse[s], row.x0, row.y);
    uint all;
    const uint place = appendPlace(hit, all);
    if (hit) list[at + place] = s;
    at += all;
    barrier();
  }
}

void main() {
  if (MODE == 0u)
    writeBoxes();
  else if (MODE == 1u)
    countChunk();
  else if (MODE == 2u)
    scanCounts();
  else if (MODE == 3u)
    fillChunk();
  else if (MODE == 4u)
    countBin();
  else
    fillBin();
}
