#version 460
// 3dr-binned, after the count pass (raster3d.comp.glsl): each tile's first list entry, and the
// fill cursors cleared. The tiles' ranges only need to be disjoint and contiguous, not in tile
// order, so one workgroup of 1024 threads gives thread i the tiles i, i + 1024, i + 2048, ...
// (32 at 1920x1080, 127 at 3840x2160):
// - each thread sums its tiles' counts, 8 at a time with the 8 loads independent so that they are
//   in flight together, and each load coalesced across the threads;
// - a Hillis-Steele scan over the 1024 sums gives each thread the start of its tiles' ranges;
// - each thread reads its counts again (from the cache), 8 at a time, and writes its tiles'
//   offsets in turn.
// Measured on the H200 at 1080p (results/h200/raster3d-52/scan): the tiles in tile order in slabs
// of 6,144, each slab scanned on its own, took 0.024 ms, most of it waiting on barriers and loads;
// each thread owning a run of consecutive tiles, whatever its loads in flight, 0.103 ms: a warp's
// loads then touch 32 cache lines each, and the one workgroup's multiprocessor serves them a line
// at a time.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared/gpu_types.h"

#include "raster3d_common.glsl.inc"
layout(local_size_x = 1024) in;

const uint kThreads = 1024u, kBatch = 8u;
shared uint sSums[kThreads];

void main() {
  const uint T = tileCount(), i = gl_LocalInvocationID.x;
  const uint per = (T + kThreads - 1u) / kThreads;  // tiles a thread (the last ones may lie past T)
  uint sum = 0u;
  for (uint k = 0u; k < per; k += kBatch) {
    uint c[kBatch];
    [[unroll]] for (uint j = 0u; j < kBatch; ++j) {
      const uint at = (k + j) * kThreads + i;
      c[j] = k + j < per && at < T ? bins[at] : 0u;
    }
    [[unroll]] for (uint j = 0u; j < kBatch; ++j) sum += c[j];
  }
  sSums[i] = sum;
  barrier();
  // Hillis-Steele inclusive scan of the 1024 thread sums.
  for (uint offset = 1u; offset < kThreads; offset <<= 1) {
    const uint add = i >= offset ? sSums[i - offset] : 0u;
    barrier();
    sSums[i] += add;
    barrier();
  }
  uint run = sSums[i] - sum;  // exclusive: the tiles of the threads before this one
  for (uint k = 0u; k < per; k += kBatch) {
    uint c[kBatch];
    [[unroll]] for (uint j = 0u; j < kBatch; ++j) {
      const uint at = (k + j) * kThreads + i;
      c[j] = k + j < per && at < T ? bins[at] : 0u;
    }
    [[unroll]] for (uint j = 0u; j < kBatch; ++j) {
      const uint at = (k + j) * kThreads + i;
      if (k + j < per && at < T) {
        bins[T + at] = run;
        bins[2u * T + at] = 0u;
        run += c[j];
      }
    }
  }
  if (ANALYSIS == 1 && i == kThreads - 1u) counters[kR3dCounterListEntries] = uint64_t(sSums[kThreads - 1u]);
}
