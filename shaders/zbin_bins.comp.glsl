#version 460
// z-binning, step 2 of 2 (Drobot 2017): per log-depth bin the [first, last] sorted light whose bin
// extent (zbin_sort.comp.glsl) contains it, packed lo | (last + 1) << 16 (lo == hi: empty), after the
// tile masks in the list buffer (FrameConstants.lists.w). One thread per bin over every light, the
// extents staged through shared memory.
#extension GL_GOOGLE_include_directive : require
#include "shared/gpu_types.h"
layout(local_size_x = 256) in;

uniform Frame { FrameConstants frame; };
buffer Indices { uint lightIndices[]; };
readonly buffer Extents { uvec2 extents[]; };
layout(push_constant) uniform Push { uint lightCount; } pc;

shared uvec2 sExtent[256];

void main() {
  const uint bin = gl_GlobalInvocationID.x;  // kZBins is a multiple of 256
  const uint n = min(pc.lightCount, kMaxLights);
  uint lo = 0xFFFFu, hi = 0u;
  for (uint base = 0u; base < n; base += 256u) {
    const uint k = base + gl_LocalInvocationIndex;
    sExtent[gl_LocalInvocationIndex] = k < n ? extents[k] : uvec2(1u, 0u);
    barrier();
    for (uint j = 0u; j < 256u; ++j) {
      const uvec2 e = sExtent[j];
      if (e.x <= bin && bin <= e.y) {
        lo = min(lo, base + j);
        hi = max(hi, base + j + 1u);
      }
    }
    barrier();
  }
  lightIndices[frame.lists.w + bin] = lo < hi ? lo | (hi << 16) : 0u;
}
