#version 460
// raybench's loads ceiling (gpu/peaks_rays.cpp measureLoadsCeiling): the loads of our wide traversal
// (compute_occluded.glsl.inc at bvh_width 4 or 8) for a ray file, each ray's nodes and triangles in
// the order the CPU replay of that traversal fetched them (gpu/trace_work.h), with none of its box
// or triangle tests, pushes or pops. A thread takes the ray the traversal's thread takes (8x8 rays a
// group, row-major over the launch). Each fetch's address depends on the fetch before it (`dep`,
// always 0, but known only at run time), as the traversal's next node depends on its tests: what
// is left is the memory's latency and throughput for exactly these addresses, in this order, with
// this divergence a subgroup of 32. It bounds the traversal's rate from above.
//  - A node: its W / 4 groups of 7 vec4 (6 of boxes and the codes), as wideChildren() loads them
//    (or of 4, kGroupLoads).
//  - A triangle: its 3 vec4.
// The events of subgroup chunk c (32 consecutive invocations of a group, a group's two chunks in
// order) start at chunkBase[c]; step s of lane l is events[chunkBase[c] + 32 s + l]. Each ray's
// count of events, with bit 31 whether the replay found no hit, is rayInfo[ray]; the ray writes that
// bit as its missed flag, so raybench's check of every ray's result holds for it too.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 8, local_size_y = 8) in;

layout(constant_id = 0) const uint kWidth = 4u;
// A group's vec4s loaded and its stride: 7 of 8 (the layout as it is), or 4 of 4 (a group of 64 B, as
// a compressed node would be: what halving the node's bytes could buy, on the same tree; the data
// read is then not the node's, which a ceiling does not need).
layout(constant_id = 1) const uint kGroupLoads = 7u;
layout(constant_id = 2) const uint kGroupStride = 8u;

layout(std430) buffer Dst { uint missedOut[]; };
layout(std430) readonly buffer BvhNodes { vec4 bvhNodes[]; };
layout(std430) readonly buffer BvhTriangles { vec4 bvhTriangles[]; };
layout(std430) readonly buffer Events { uint events[]; };
layout(std430) readonly buffer ChunkBase { uint chunkBase[]; };
layout(std430) readonly buffer RayInfo { uint rayInfo[]; };
layout(push_constant) uniform Size {
  uvec2 size;  // the launch
  uint rays;   // the file's rays (the launch may hold more)
  uint zero;   // 0, from the host: the compiler cannot fold acc & zero away
};

void main() {
  const uvec2 id = gl_GlobalInvocationID.xy;
  if (id.x >= size.x || id.y >= size.y) return;
  const uint index = id.y * size.x + id.x;
  if (index >= rays) return;
  const uint tile = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  const uint chunk = 2u * tile + gl_LocalInvocationIndex / 32u, lane = gl_LocalInvocationIndex % 32u;
  const uint info = rayInfo[index], n = info & 0x7FFFFFFFu, base = chunkBase[chunk];
  uint acc = 0u, dep = 0u;
  for (uint s = 0u; s < n; ++s) {
    const uint e = events[base + 32u * s + lane] + dep;
    if (e < 0x80000000u) {
      for (uint g = 0u; g < kWidth / 4u; ++g) {
        const uint b = (kWidth / 4u) * kGroupStride * e + kGroupStride * g;
        for (uint k = 0u; k < kGroupLoads; ++k) {
          const uvec4 v = floatBitsToUint(bvhNodes[b + k]);
          acc ^= v.x ^ v.y ^ v.z ^ v.w;
        }
      }
    } else {
      const uint t = 3u * (e & 0x7FFFFFFFu);
      for (uint k = 0u; k < 3u; ++k) {
        const uvec4 v = floatBitsToUint(bvhTriangles[t + k]);
        acc ^= v.x ^ v.y ^ v.z ^ v.w;
      }
    }
    dep = acc & zero;  // 0, but known only at run time: the next address waits for these loads
  }
  // The loads stay live: the flag depends on acc.
  missedOut[index] = (info >> 31) | (acc & zero);
}
