#version 460
// Layered depth maps, the hardware build's fragment: each fragment takes a node from the pool and
// inserts its depth into its pixel's list (ldm_insert.glsl.inc: ldm_list = max64 or cas), or is
// counted or written in place (sbuffer).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_buffer_reference : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "shared/gpu_types.h"

#include "ldm_build_constants.glsl.inc"
layout(push_constant) uniform Push { DrawConstants draw; };

uniform LinksAddress { uvec2 linksAddress; };  // gpu_types.h layouts
buffer Counters { uint counters[]; };

#include "ldm_insert.glsl.inc"

layout(location = 0) flat in uint inMap;
layout(location = 1) in float inDepth;

void main() {
  const uint pixel = inMap * RESOLUTION * RESOLUTION + uint(gl_FragCoord.y) * RESOLUTION + uint(gl_FragCoord.x);
  if (LIST == kLdmListSbuffer) {  // no nodes to take: the scan placed every fragment
    ldmSbuffer(linksAddress, pixel, inDepth, draw.triangleBase + uint(gl_PrimitiveID));
    return;
  }
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
  ldmInsert(linksAddress, pixel, node, inDepth);
}
