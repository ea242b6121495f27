#version 460
// 3dr-binned, after the count pass (raster3d.comp.glsl): the exclusive prefix sum of the per-tile
// counts, each tile's first list entry, with the fill cursors cleared. One workgroup of 1024
// threads, each a contiguous chunk of tiles (129,600 tiles at 3840x2160: 127 per thread).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared/gpu_types.h"

#include "raster3d_common.glsl.inc"
layout(local_size_x = 1024) in;

shared uint sChunk[1024];

void main() {
  const uint T = tileCount(), i = gl_LocalInvocationID.x, chunk = (T + 1023u) / 1024u;
  const uint first = min(i * chunk, T), last = min(first + chunk, T);
  uint sum = 0u;
  for (uint k = first; k < last; ++k) sum += bins[k];
  sChunk[i] = sum;
  barrier();
  // Hillis-Steele inclusive scan of the 1024 chunk sums.
  for (uint offset = 1u; offset < 1024u; offset <<= 1) {
    const uint add = i >= offset ? sChunk[i - offset] : 0u;
    barrier();
    sChunk[i] += add;
    barrier();
  }
  if (ANALYSIS == 1 && i == 1023u) counters[kR3dCounterListEntries] = uint64_t(sChunk[1023]);
  uint run = sChunk[i] - sum;  // exclusive
  for (uint k = first; k < last; ++k) {
    bins[T + k] = run;
    bins[2u * T + k] = 0u;
    run += bins[k];
  }
}
