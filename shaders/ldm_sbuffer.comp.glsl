#version 460
// Layered depth maps, ldm_list = sbuffer (gpu_types.h): between the count and the fill pass the
// per-pixel counts become offsets by an exclusive scan in place (blocks of 4096 counts: STAGE 0 sums
// each block, STAGE 1 scans the block sums in one workgroup and writes the total, STAGE 2 scans each
// block from its base); after the fill pass STAGE 3 sorts each pixel's range by (depth, triangle id)
// (ranges are short: 2.2 entries a pixel on the atrium, at most ~100; up to 16 are ranked in
// registers, longer ones insertion-sorted in place), so the words do not depend on the order
// fragments arrived in.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_control_flow_attributes : require
#include "shared/gpu_types.h"

layout(constant_id = 0) const uint STAGE = 0;
layout(constant_id = 1) const uint PIXELS = 1;
layout(constant_id = 2) const uint NODE_CAPACITY = 1;
layout(local_size_x_id = 3) in;  // 256 (stages 0, 2, 3) or 1024 (stage 1)

layout(buffer_reference, std430, buffer_reference_align = 4) buffer Words { uint words[]; };
uniform LinksAddress { uvec2 linksAddress; };
buffer Counters { uint counters[]; };
buffer BlockSums { uint blockSums[]; };

const uint kPerThread = 16u, kBlock = 256u * kPerThread;
const uint kLocal = 16u;  // STAGE 3: ranges up to this long are ranked in registers
shared uint sScan[1024];

// Exclusive scan of one value per invocation over the workgroup (Hillis-Steele in shared memory);
// returns the invocation's prefix and leaves the total in `total`.
uint workgroupExclusiveScan(uint v, out uint total) {
  const uint i = gl_LocalInvocationIndex, n = gl_WorkGroupSize.x;
  sScan[i] = v;
  barrier();
  for (uint d = 1u; d < n; d <<= 1u) {
    const uint add = i >= d ? sScan[i - d] : 0u;
    barrier();
    sScan[i] += add;
    barrier();
  }
  total = sScan[n - 1u];
  return sScan[i] - v;
}

void main() {
  Words w = Words(uint64_t(linksAddress.x) | (uint64_t(linksAddress.y) << 32));
  const uint blocks = (PIXELS + kBlock - 1u) / kBlock;
  if (STAGE == 0u || STAGE == 2u) {
    const uint b = gl_WorkGroupID.x;
    const uint first = b * kBlock + gl_LocalInvocationIndex * kPerThread;
    uint sum = 0u;
    for (uint k = 0u; k < kPerThread; ++k)
      if (first + k < PIXELS) sum += w.words[first + k];
    uint total;
    const uint prefix = workgroupExclusiveScan(sum, total);
    if (STAGE == 0u) {
      if (gl_LocalInvocationIndex == 0u) blockSums[b] = total;
      return;
    }
    uint running = blockSums[b] + prefix;
    for (uint k = 0u; k < kPerThread; ++k)
      if (first + k < PIXELS) {
        const uint count = w.words[first + k];
        w.words[first + k] = running;
        running += count;
      }
  } else if (STAGE == 1u) {
    const uint per = (blocks + 1023u) / 1024u, first = gl_LocalInvocationIndex * per;
    uint sum = 0u;
    for (uint k = 0u; k < per; ++k)
      if (first + k < blocks) sum += blockSums[first + k];
    uint total;
    uint running = workgroupExclusiveScan(sum, total);
    for (uint k = 0u; k < per; ++k)
      if (first + k < blocks) {
        const uint s = blockSums[first + k];
        blockSums[first + k] = running;
        running += s;
      }
    if (gl_LocalInvocationIndex == 0u) {
      w.words[PIXELS] = total;  // the end of the last range
      counters[kLdmCounterAllocated] = total;
    }
  } else {
    const uint pixel = (gl_WorkGroupID.y * 1024u + gl_WorkGroupID.x) * 256u + gl_LocalInvocationIndex;
    if (pixel >= PIXELS) return;
    const uint depths = 2u * PIXELS + 1u, ids = depths + NODE_CAPACITY;
    const uint begin = min(w.words[pixel], NODE_CAPACITY), end = min(w.words[pixel + 1u], NODE_CAPACITY);
    if (end - begin < 2u) return;
    const uint n = end - begin;
    if (n <= kLocal) {
      // A short range (p99 12 entries on the atrium): read once into registers (constant indices,
      // unrolled), each entry's place is the count of entries before it in (depth, id) order (no
      // two are equal: a triangle crosses a pixel's line once), written once. The insertion sort
      // below waits on a dependent load per step (2.85 ms for 512 maps of 256² on the H200).
      uint d[kLocal], t[kLocal];
      [[unroll]] for (uint k = 0u; k < kLocal; ++k) {
        d[k] = k < n ? w.words[depths + begin + k] : 0u;
        t[k] = k < n ? w.words[ids + begin + k] : 0u;
      }
      [[unroll]] for (uint k = 0u; k < kLocal; ++k) {
        if (k >= n) break;
        const float zk = uintBitsToFloat(d[k]);
        uint rank = 0u;
        [[unroll]] for (uint j = 0u; j < kLocal; ++j) {
          const float zj = uintBitsToFloat(d[j]);
          rank += (j < n && (zj < zk || (zj == zk && t[j] < t[k]))) ? 1u : 0u;
        }
        w.words[depths + begin + rank] = d[k];
        w.words[ids + begin + rank] = t[k];
      }
      return;
    }
    for (uint a = begin + 1u; a < end; ++a) {
      const uint kd = w.words[depths + a], ki = w.words[ids + a];
      const float kz = uintBitsToFloat(kd);
      uint b = a;
      while (b > begin) {
        const float z = uintBitsToFloat(w.words[depths + b - 1u]);
        if (z < kz || (z == kz && w.words[ids + b - 1u] <= ki)) break;
        w.words[depths + b] = w.words[depths + b - 1u];
        w.words[ids + b] = w.words[ids + b - 1u];
        --b;
      }
      w.words[depths + b] = kd;
      w.words[ids + b] = ki;
    }
  }
}
