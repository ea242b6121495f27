#version 460
// z-binning, step 1 of 2 (Drobot 2017; frame/passes/light_culling.h): the lights sorted by the view
// distance of their centres (directional lights first), ties by index, as a rank per light: each
// workgroup computes every light's key into shared memory with the same code (so every workgroup
// sees the same keys), then each thread counts the keys before its own. O(lights²) compares, a few
// microseconds at 4096 lights. Writes the sorted lights, the sorted-to-scene index map and each
// sorted light's bin extent [lo, hi] (zbinExtent).
#extension GL_GOOGLE_include_directive : require
#include "culling.glsl.inc"
layout(local_size_x = 256) in;

uniform Frame { FrameConstants frame; };
readonly buffer Lights { GpuLight lights[]; };
writeonly buffer SortedLights { GpuLight sortedLights[]; };
writeonly buffer Order { uint order[]; };           // sorted -> scene index
writeonly buffer Extents { uvec2 extents[]; };      // per sorted light: bins [lo, hi]
layout(push_constant) uniform Push { uint lightCount; } pc;

shared float sKey[kMaxLights];

float sortKey(GpuLight l) { return l.type == kLightDirectional ? -3.0e38 : -lightViewPosition(l, frame.view).z; }

// The bins a light can reach: its centre's view distance ± (range + w), w = 16u·(|d| + r + |light| +
// |view translation|) covering the float rounding of the view transform (as sliceWidening), then one
// bin more on each side for the rounding of a pixel's own distance and of log2 (a bin is
// ln(far/near)/kZBins ≈ 0.2 % of the distance wide, far above a few float ulps). A light wholly behind
// the eye reaches no bin (lo > hi).
uvec2 zbinExtent(GpuLight l) {
  if (l.type == kLightDirectional) return uvec2(0u, kZBins - 1u);
  float d = -lightViewPosition(l, frame.view).z, r = l.positionRange.w;
  float w = 16.0 * 5.9604644775390625e-8 * (abs(d) + r + length(l.positionRange.xyz) + length(frame.view[3].xyz));
  if (d + r + w < 0.0) return uvec2(1u, 0u);
  uint lo = zbinOf(max(d - r - w, 0.0), frame.zbins), hi = zbinOf(d + r + w, frame.zbins);
  return uvec2(lo > 0u ? lo - 1u : 0u, min(hi + 1u, kZBins - 1u));
}

void main() {
  const uint n = min(pc.lightCount, kMaxLights);
  for (uint j = gl_LocalInvocationIndex; j < n; j += 256u) sKey[j] = sortKey(lights[j]);
  barrier();
  const uint i = gl_GlobalInvocationID.x;
  if (i >= n) return;
  const float key = sKey[i];
  uint rank = 0u;
  for (uint j = 0u; j < n; ++j) rank += (sKey[j] < key || (sKey[j] == key && j < i)) ? 1u : 0u;
  sortedLights[rank] = lights[i];
  order[rank] = i;
  extents[rank] = zbinExtent(lights[i]);
}
