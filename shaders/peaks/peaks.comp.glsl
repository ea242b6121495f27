#version 460
// The device's own ceilings (gpu/peaks.cpp, `hybridbench peaks`): one kernel per MODE, each a
// grid-stride loop so that any dispatch size covers any element count. What each counts:
//   READ      16 B read per element (uvec4), summed; the sum is written only where it equals a
//             value the shader cannot know (push.sentinel), so no compiler can drop the loads.
//   WRITE     16 B written per element.
//   COPY      16 B read + 16 B written per element.
//   ATOMIC    one 32-bit atomicAdd per element to its own word (distinct addresses, coalesced).
//   CONTENDED one 32-bit atomicAdd per element to its workgroup's one word (256 threads contend).
//   FMA       push.iterations x 8 independent fma chains per thread (8 FMAs an iteration); the
//             result is written only where it equals the sentinel.
#extension GL_GOOGLE_include_directive : require

layout(constant_id = 0) const uint MODE = 0u;
const uint kRead = 0u, kWrite = 1u, kCopy = 2u, kAtomic = 3u, kContended = 4u, kFma = 5u;

layout(local_size_x = 256) in;
layout(push_constant) uniform Push {
  uint elements;    // uvec4 elements (READ, WRITE, COPY), atomic operations, or FMA threads
  uint iterations;  // FMA: iterations of its loop
  uint sentinel;    // a value no element sums to in practice (keeps the loads and FMAs alive)
  uint pad;
}
push;

layout(std430) readonly buffer Src { uvec4 src[]; };
layout(std430) buffer Dst { uvec4 dst[]; };
layout(std430) buffer DstWords { uint words[]; };

void main() {
  const uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  const uint first = gl_GlobalInvocationID.x;
  if (MODE == kRead) {
    uvec4 sum = uvec4(0u);
    for (uint i = first; i < push.elements; i += stride) sum += src[i];
    if (sum.x + sum.y + sum.z + sum.w == push.sentinel) dst[first] = sum;
  } else if (MODE == kWrite) {
    for (uint i = first; i < push.elements; i += stride) dst[i] = uvec4(i);
  } else if (MODE == kCopy) {
    for (uint i = first; i < push.elements; i += stride) dst[i] = src[i];
  } else if (MODE == kAtomic) {
    for (uint i = first; i < push.elements; i += stride) atomicAdd(words[i], 1u);
  } else if (MODE == kContended) {
    for (uint i = first; i < push.elements; i += stride) atomicAdd(words[gl_WorkGroupID.x], 1u);
  } else if (first < push.elements) {  // FMA
    const float x = float(first) * 1e-7;
    float a0 = x, a1 = x + 1.0, a2 = x + 2.0, a3 = x + 3.0, a4 = x + 4.0, a5 = x + 5.0, a6 = x + 6.0, a7 = x + 7.0;
    const float m = 0.9999, c = 1e-4;
    for (uint k = 0u; k < push.iterations; ++k) {
      a0 = fma(a0, m, c); a1 = fma(a1, m, c); a2 = fma(a2, m, c); a3 = fma(a3, m, c);
      a4 = fma(a4, m, c); a5 = fma(a5, m, c); a6 = fma(a6, m, c); a7 = fma(a7, m, c);
    }
    const float r = a0 + a1 + a2 + a3 + a4 + a5 + a6 + a7;
    if (floatBitsToUint(r) == push.sentinel) words[first] = floatBitsToUint(r);
  }
}
