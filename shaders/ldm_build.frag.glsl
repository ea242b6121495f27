#version 460
// Layered depth maps, list insertion (ldm_list = max64): each fragment takes a node from the pool
// and inserts its record (key << 32 | node, gpu_types.h) into the pixel's list, kept in descending
// record order (= ascending depth) by 64-bit atomicMax alone: at a link, atomicMax(link, cur)
// either leaves a larger record there (move on to that record's next link) or puts cur there and
// hands back the smaller record it displaced, which then goes on into cur's own next link. Every
// step keeps every list sorted and complete, so concurrent insertions need no lock. Equal depths
// order by node, which depends on allocation order: the depths of a list are deterministic, the
// nodes are not. A full pool and an insertion longer than kLdmMaxInsertSteps are counted.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_buffer_reference : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "shared/gpu_types.h"

layout(constant_id = 0) const uint RESOLUTION = 128;
layout(constant_id = 1) const uint NODE_CAPACITY = 1;
layout(constant_id = 2) const uint PIXELS = 1;  // maps × RESOLUTION²

// PIXELS heads, then NODE_CAPACITY next links, through the buffer's device address (gpu_types.h).
layout(buffer_reference, std430, buffer_reference_align = 8) buffer LdmLinks { uint64_t links[]; };
layout(set = 0, binding = 1) uniform LinksAddress { uvec2 linksAddress; };
layout(set = 0, binding = 2) buffer Counters { uint counters[]; };

layout(location = 0) flat in uint inMap;
layout(location = 1) in float inDepth;

void main() {
  const uint pixel = inMap * RESOLUTION * RESOLUTION + uint(gl_FragCoord.y) * RESOLUTION + uint(gl_FragCoord.x);
  // Nodes are taken a subgroup at a time (one atomic on the pool's counter per subgroup, not per
  // fragment: millions of fragments on one address serialize). Helper invocations take none (their
  // writes are discarded), so the leader is the lowest real invocation, and its base reaches the
  // others through a max over the subgroup (everyone else holds 0).
  const uvec4 real = subgroupBallot(!gl_HelperInvocation);
  uint base = 0u;
  if (gl_SubgroupInvocationID == subgroupBallotFindLSB(real))
    base = atomicAdd(counters[kLdmCounterAllocated], subgroupBallotBitCount(real));
  base = subgroupMax(base);
  if (gl_HelperInvocation) return;
  const uint node = base + subgroupBallotExclusiveBitCount(real) + 1u;
  if (node > NODE_CAPACITY) {
    atomicAdd(counters[kLdmCounterOverflow], 1u);
    return;
  }
  const uint key = kLdmKeyTop - floatBitsToUint(max(inDepth, 0.0));
  uint64_t cur = (uint64_t(key) << 32) | uint64_t(node);
  LdmLinks l = LdmLinks(uint64_t(linksAddress.x) | (uint64_t(linksAddress.y) << 32));
  uint link = pixel;
  for (uint step = 0u; step < kLdmMaxInsertSteps; ++step) {
    const uint64_t old = atomicMax(l.links[link], cur);
    if (old == 0ul) return;  // cur ends the list
    if (old < cur) {         // cur took this link; the displaced record goes on after cur
      link = PIXELS + uint(cur & 0xFFFFFFFFul) - 1u;
      cur = old;
    } else {
      link = PIXELS + uint(old & 0xFFFFFFFFul) - 1u;
    }
  }
  atomicAdd(counters[kLdmCounterUnfinished], 1u);
}
