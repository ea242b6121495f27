#version 460
// Primary visibility by frusta through a BVH (Davidovic et al. 2012, Sect. 4, Fig. 7): the methods
// "3dr-frustum-cull", "3dr-frustum-split" and "3dr-full". One workgroup of 256 threads owns a
// screen frustum of F = 8 << FRUSTUM_LOG2 pixels a side (r3d_frustum) and every pixel in it:
//
//   traverse(F, N): if isOutside or isOccluded: return        (Fig. 6a)
//                   if splitFrustum: traverse(F_i, N), i < 4    (Fig. 6b, c)
//                   else if N is a leaf: rasterize(N, binning)  (Fig. 6d)
//                   else: traverse(F, child) for both children, the nearer first
//
// The recursion is a stack of (node, frustum) entries in shared memory; each step the 64 threads
// pop up to 64 entries and run the oracles on one each (the first 64 threads), pushing what follows. A leaf's triangles
// go to a queue that is rasterized after the step (so depth is there for the next step's
// occlusion tests), 64 triangles at a time: each thread sets one up (3DR, raster3d.glsl.inc) and
// clips its screen box to the entry's frustum, then lists the box's 8x8 blocks (BINNING: only
// blocks whose corner edge values can reach a pixel centre, tileMayBeCovered; EARLYZ: only blocks
// whose farthest depth so far is not nearer than the triangle), and the workgroup rasterizes the
// list four blocks at a time, a pixel per thread, with one atomicMin per covered pixel.
//
// The oracles, each conservative, so the visibility buffer equals brute force ("3dr") bit for bit:
//  - isOutside: the node's box is outside one of the planes through the eye and the pixel-centre
//    rays one pixel beyond the frustum's edges (a pixel centre of the frustum is a whole pixel
//    inside each), or wholly before znear/2 or past zfar; with a margin for the float evaluation.
//  - isOccluded (OCCLUSION): the box's nearest forward depth, less a margin, is farther than the
//    farthest depth so far of every pixel of the frustum (a hierarchical depth, "HiZ": per 8x8
//    block of the top frustum and every power-of-two level up to it, in shared memory). A triangle
//    there gives each pixel a larger t, hence a larger key, whatever its id: nothing changes.
//  - splitFrustum (SPLIT): the frustum is larger than 8 << MIN_LOG2 (r3d_min_frustum) and its
//    centre ray misses the box, or the box spans less than half the frustum on screen.
// A push that finds the stack full rasterizes the node's whole subtree over the frustum in the
// pushing thread (slow, never a dropped pixel; counted as bvh_stack_overflows).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#include "shared/gpu_types.h"

#define R3D_BVH  // raster3d_common.glsl.inc: rasterizeBox keeps the exact test at every pixel
#include "raster3d_common.glsl.inc"
// 256 threads: the first 64 traverse and set triangles up; all four groups of 64 rasterize, four
// blocks at a time (64 threads alone left too few warps on an SM to hide memory latency).
layout(local_size_x = 256) in;
const uint kGroups = 4u;

layout(constant_id = 6) const uint SPLIT = 0;          // the splitFrustum oracle
layout(constant_id = 7) const uint OCCLUSION = 0;      // the isOccluded oracle
layout(constant_id = 8) const uint BINNING = 1;        // a leaf triangle's blocks tested at their corners first
layout(constant_id = 9) const uint EARLYZ = 0;         // blocks behind the depth so far skipped
layout(constant_id = 10) const uint FRUSTUM_LOG2 = 5;  // the top frustum: 8 << this pixels a side (<= 5)
layout(constant_id = 11) const uint MIN_LOG2 = 0;      // split down to 8 << this pixels
layout(constant_id = 12) const uint STACK_LIMIT = 768; // the stack's entries (tests lower it to reach the fallback)
const bool HIZ = OCCLUSION == 1u || EARLYZ == 1u;

const uint kStack = 768u, kQueue = 256u, kBlocks = 512u;
const uint kHizSize = 1365u;      // levels 0..5 of a 256-px frustum: 32² + 16² + 8² + 4² + 2² + 1
const uint kNoDepth = 0xFFFFFFFFu;  // a pixel with no hit yet: nothing behind it can be culled
const float kU = 5.9604644775390625e-8;  // 2^-24

shared uvec2 sStack[kStack];  // (node, frustum rect)
shared uint sTop;
shared uint sQueueId[kQueue];
shared uint sQueueRect[kQueue];
shared uint sQueueCount;
shared R3dSetup sSetup[64];
shared ivec4 sBox[64];  // the chunk's triangles' boxes clipped to their frusta; empty when hi < lo
shared uint sId[64];
shared uint sBlock[kBlocks];  // (chunk entry | block x << 6 | block y << 19)
shared uint sBlockCount;
shared uint sPending;
shared uint sHiz[kHizSize];  // max t bits over each block's pixels (kNoDepth: some pixel has none)
shared uint sBlockMax[kGroups];

// A frustum rect: its first pixel / 8 (x: 12 bits, y: 12 bits) and its level (size 8 << level).
uint packRect(uvec2 origin, uint level) { return (origin.x / 8u) | ((origin.y / 8u) << 12) | (level << 24); }
uvec2 rectOrigin(uint rect) { return uvec2(rect & 0xFFFu, (rect >> 12) & 0xFFFu) * 8u; }
uint rectLevel(uint rect) { return rect >> 24; }
// Its pixels on screen, inclusive: (xa, ya, xb, yb); empty when off screen.
ivec4 rectPixels(uint rect) {
  const uvec2 o = rectOrigin(rect);
  const uint size = 8u << rectLevel(rect);
  return ivec4(o, min(ivec2(o + size) - 1, ivec2(r3.width, r3.height) - 1));
}

uint frustaX() { return (r3.width + (8u << FRUSTUM_LOG2) - 1u) / (8u << FRUSTUM_LOG2); }
uvec2 frustumOrigin() {
  return uvec2(gl_WorkGroupID.x % frustaX(), gl_WorkGroupID.x / frustaX()) * (8u << FRUSTUM_LOG2);
}

// The HiZ entry of a rect (aligned, inside this workgroup's frustum) at its level.
uint hizIndex(uint rect) {
  const uint level = rectLevel(rect);
  uint offset = 0u;
  for (uint l = 0u; l < level; ++l) offset += 1u << (2u * (FRUSTUM_LOG2 - l));
  const uvec2 local = (rectOrigin(rect) - frustumOrigin()) / (8u << level);
  return offset + local.y * (1u << (FRUSTUM_LOG2 - level)) + local.x;
}

vec3 rayDir(float x, float y) { return r3.rayD0.xyz + x * r3.rayDx.xyz + y * r3.rayDy.xyz; }

// Is the box wholly on the negative side of the plane through the eye with normal n? Its largest
// dot(n, p − eye) is at the corner picked by n's signs; the margin covers that evaluation's
// rounding and the rounding of the eye-relative vertices the rasterizer sets up (u each).
bool outsidePlane(vec3 n, vec3 lo, vec3 hi) {
  const vec3 corner = mix(lo, hi, greaterThan(n, vec3(0.0)));
  const float v = dot(n, corner) - dot(n, r3.eye.xyz);
  const float err = 16.0 * kU * dot(abs(n), max(abs(lo), abs(hi)) + abs(r3.eye.xyz));
  return v < -err;
}

// The box's forward depth range (t of any point in it; t is the forward depth, d's forward
// component being 1), widened by its evaluation's rounding.
vec2 boxDepth(vec3 lo, vec3 hi) {
  const vec3 f = r3.forward.xyz;
  const bvec3 pos = greaterThan(f, vec3(0.0));
  const float e = dot(r3.eye.xyz, f);
  const float err = 16.0 * kU * dot(abs(f), max(abs(lo), abs(hi)) + abs(r3.eye.xyz));
  return vec2(dot(mix(hi, lo, pos), f) - e - err, dot(mix(lo, hi, pos), f) - e + err);
}

// isOutside: the four side planes one pixel beyond the rect's edge centres, znear/2 and zfar.
bool outsideFrustum(vec3 lo, vec3 hi, ivec4 r, vec2 z) {
  if (z.y < 0.5 * r3.depth.x || z.x > r3.depth.y) return true;
  const vec3 dx = r3.rayDx.xyz, dy = r3.rayDy.xyz;
  vec3 nl = cross(rayDir(float(r.x) - 1.0, 0.0), dy);
  vec3 nr = cross(rayDir(float(r.z) + 1.0, 0.0), dy);
  vec3 nt = cross(rayDir(0.0, float(r.y) - 1.0), dx);
  vec3 nb = cross(rayDir(0.0, float(r.w) + 1.0), dx);
  // d(x, y)·n_l = (x − x_l)·(dx·n_l): oriented so that the rect's side is positive.
  nl *= sign(dot(nl, dx));
  nr *= -sign(dot(nr, dx));
  nt *= sign(dot(nt, dy));
  nb *= -sign(dot(nb, dy));
  return outsidePlane(nl, lo, hi) || outsidePlane(nr, lo, hi) || outsidePlane(nt, lo, hi) || outsidePlane(nb, lo, hi);
}

bool occluded(float zmin, uint rect) {
  const uint h = sHiz[hizIndex(rect)];
  return h != kNoDepth && zmin * (1.0 - 1.0 / 1024.0) > uintBitsToFloat(h);
}

// splitFrustum: the centre ray misses the box (slab test), or the box spans less than half the
// frustum (its diagonal over the pixel footprint at its nearest depth).
bool splitOracle(vec3 lo, vec3 hi, ivec4 r, float zmin) {
  const vec3 d = rayDir(0.5 * float(r.x + r.z), 0.5 * float(r.y + r.w));
  const vec3 inv = 1.0 / d;
  const vec3 t0 = (lo - r3.eye.xyz) * inv, t1 = (hi - r3.eye.xyz) * inv;
  const vec3 tn = min(t0, t1), tf = max(t0, t1);
  const float enter = max(max(tn.x, tn.y), max(tn.z, 0.0)), leave = min(tf.x, min(tf.y, tf.z));
  if (!(enter <= leave)) return true;
  const float side = float(max(r.z - r.x, r.w - r.y) + 1);
  const float px = length(hi - lo) / (max(zmin, r3.depth.x) * length(r3.rayDx.xyz));
  return px < 0.5 * side;
}

struct Work {
  uint nodes, splits, culledFrustum, culledOcclusion, earlyZ, overflows, setups;
};

void pushEntry(uvec2 entry, inout Work work, inout Tally tally) {
  const uint slot = atomicAdd(sTop, 1u);
  if (slot < min(kStack, STACK_LIMIT)) {
    sStack[slot] = entry;
    return;
  }
  // The stack is full: the node's whole subtree over the rect, in this thread.
  if (ANALYSIS == 1) ++work.overflows;
  const PrimaryBvhNode node = bvhNodes[entry.x];
  const ivec4 r = rectPixels(entry.y);
  for (uint k = 0u; k < node.info.z; ++k) {
    const uint id = bvhOrder[node.info.y + k];
    R3dSetup s;
    ivec2 lo, hi;
    if (!setupTriangle(id, s, lo, hi)) continue;
    const ivec2 a = max(lo, r.xy), b = min(hi, r.zw);
    if (b.x >= a.x && b.y >= a.y) rasterizeBox(id, s, uvec2(a), b, tally);
  }
}

void visit(uvec2 entry, inout Work work, inout Tally tally) {
  const PrimaryBvhNode node = bvhNodes[entry.x];
  const uint rect = entry.y;
  const ivec4 r = rectPixels(rect);
  const vec3 lo = node.lo.xyz, hi = node.hi.xyz;
  if (ANALYSIS == 1) ++work.nodes;
  const vec2 z = boxDepth(lo, hi);
  if (outsideFrustum(lo, hi, r, z)) {
    if (ANALYSIS == 1) work.culledFrustum += node.info.z;
    return;
  }
  if (OCCLUSION == 1u && occluded(z.x, rect)) {
    if (ANALYSIS == 1) work.culledOcclusion += node.info.z;
    return;
  }
  const uint level = rectLevel(rect);
  if (SPLIT == 1u && level > MIN_LOG2 && splitOracle(lo, hi, r, z.x)) {
    if (ANALYSIS == 1) ++work.splits;
    const uvec2 o = rectOrigin(rect);
    const uint half_ = 4u << level;
    for (uint q = 0u; q < 4u; ++q) {
      const uvec2 oq = o + uvec2(q & 1u, q >> 1) * half_;
      if (oq.x < r3.width && oq.y < r3.height) pushEntry(uvec2(entry.x, packRect(oq, level - 1u)), work, tally);
    }
    return;
  }
  if (node.info.x == 0u) {  // a leaf: its triangles to the queue (kQueue = 64 threads x kPrimaryBvhLeaf)
    const uint n = min(node.info.z, 4u);
    const uint slot = atomicAdd(sQueueCount, n);
    for (uint k = 0u; k < n; ++k) {
      sQueueId[slot + k] = bvhOrder[node.info.y + k];
      sQueueRect[slot + k] = rect;
    }
    return;
  }
  // Both children, the nearer popped first (pushed last).
  const uint left = entry.x + 1u, right = node.info.x;
  const vec3 f = r3.forward.xyz;
  const float dl = dot(bvhNodes[left].lo.xyz + bvhNodes[left].hi.xyz, f);
  const float dr = dot(bvhNodes[right].lo.xyz + bvhNodes[right].hi.xyz, f);
  const bool leftFirst = dl <= dr;
  pushEntry(uvec2(leftFirst ? right : left, rect), work, tally);
  pushEntry(uvec2(leftFirst ? left : right, rect), work, tally);
}

// Level 0 of the HiZ after block (bx, by) changed: its new farthest depth, then every level up.
// Two groups may have reduced the same block: each value bounds its current farthest depth from
// above (a pixel's key only decreases), so the smaller one is kept.
void updateHiz(uvec2 block, uint blockMax) {
  const uvec2 local = block - frustumOrigin() / 8u;
  const uint at = local.y * (1u << FRUSTUM_LOG2) + local.x;
  sHiz[at] = min(sHiz[at], blockMax);
  uint offset = 0u;
  for (uint l = 1u; l <= FRUSTUM_LOG2; ++l) {
    const uint side = 1u << (FRUSTUM_LOG2 - l + 1u), childOffset = offset;
    offset += side * side;
    const uvec2 c = (local >> l) << 1;  // the first child at level l − 1
    const uint m = max(max(sHiz[childOffset + c.y * side + c.x], sHiz[childOffset + c.y * side + c.x + 1u]),
                       max(sHiz[childOffset + (c.y + 1u) * side + c.x], sHiz[childOffset + (c.y + 1u) * side + c.x + 1u]));
    sHiz[offset + (local.y >> l) * (side / 2u) + (local.x >> l)] = m;
  }
}

// The queue's triangles over their frusta, 64 at a time (the queue is drained every step).
void rasterizeQueue(inout Work work, inout Tally tally) {
  const uint lid = gl_LocalInvocationID.x, lane = lid & 63u, group = lid >> 6;
  const uint total = sQueueCount;
  for (uint base = 0u; base < total; base += 64u) {  // uniform
    const uint e = base + lid;
    ivec4 box = ivec4(0, 0, -1, -1);
    float zmin = 0.0;
    if (lid < 64u && e < total) {
      const uint id = sQueueId[e];
      R3dSetup s;
      ivec2 lo, hi;
      if (setupTriangle(id, s, lo, hi)) {
        const ivec4 r = rectPixels(sQueueRect[e]);
        box = ivec4(max(lo, r.xy), min(hi, r.zw));
        zmin = r3dNearestDepth(s);
      }
      if (ANALYSIS == 1) ++work.setups;
      sSetup[lid] = s;
      sId[lid] = id;
    }
    if (lid < 64u) sBox[lid] = box;
    // This thread's blocks: the 8x8 screen blocks its clipped box overlaps.
    const uvec2 b0 = uvec2(max(box.xy, ivec2(0))) / 8u;
    const uint bw = box.z >= box.x ? uint(box.z) / 8u - b0.x + 1u : 0u;
    const uint nBlocks = box.w >= box.y ? bw * (uint(box.w) / 8u - b0.y + 1u) : 0u;
    uint next = 0u;
    while (true) {  // uniform: every thread leaves at the same round
      barrier();
      if (lid == 0u) {
        sBlockCount = 0u;
        sPending = 0u;
      }
      barrier();
      while (next < nBlocks) {
        const uvec2 blk = b0 + uvec2(next % bw, next / bw);
        bool keep = true;
        if (BINNING == 1u || EARLYZ == 1u) {
          uvec2 a;
          ivec2 b;
          tileInBox(blk.x, blk.y, box.xy, box.zw, a, b);
          if (BINNING == 1u) keep = tileMayBeCovered(sSetup[lid], a.x, a.y, b);
          if (keep && EARLYZ == 1u) {
            const uint h = sHiz[(blk.y - frustumOrigin().y / 8u) * (1u << FRUSTUM_LOG2) + blk.x - frustumOrigin().x / 8u];
            if (h != kNoDepth && zmin > uintBitsToFloat(h)) {
              keep = false;
              if (ANALYSIS == 1) ++work.earlyZ;
            }
          }
        }
        if (keep) {
          const uint slot = atomicAdd(sBlockCount, 1u);
          if (slot >= kBlocks) {  // full: this block again next round
            atomicAdd(sPending, 1u);
            break;
          }
          sBlock[slot] = lid | (blk.x << 6) | (blk.y << 19);
        }
        ++next;
      }
      barrier();
      const uint count = min(sBlockCount, kBlocks);
      for (uint k0 = 0u; k0 < count; k0 += kGroups) {  // uniform; group g takes item k0 + g
        const bool valid = k0 + group < count;
        const uint item = valid ? sBlock[k0 + group] : 0u;
        const uint j = item & 63u;
        const uvec2 blk = uvec2((item >> 6) & 0x1FFFu, item >> 19);
        const uint x = blk.x * 8u + lane % 8u, y = blk.y * 8u + lane / 8u;
        const ivec4 b = sBox[j];
        const bool onScreen = valid && x < r3.width && y < r3.height;
        uint64_t best = ~0ul;
        bool known = false;
        if (valid && int(x) >= b.x && int(y) >= b.y && int(x) <= b.z && int(y) <= b.w) {
          uint64_t key;
          if (pixelKey(sId[j], sSetup[j], x, y, tally, key)) {
            best = min(atomicMin(vis[y * r3.width + x], key), key);
            ++tally.atomics;
            known = true;
          }
        }
        if (!HIZ) continue;
        // The block's farthest depth now: every pixel's current key (an atomic read where this
        // item did not just write it), reduced in shared memory.
        if (onScreen && !known) best = atomicMin(vis[y * r3.width + x], ~0ul);
        if (lane == 0u) sBlockMax[group] = 0u;
        barrier();
        if (onScreen) atomicMax(sBlockMax[group], uint(best >> 32));
        barrier();
        if (lid == 0u)
          for (uint g = 0u; g < kGroups && k0 + g < count; ++g) {
            const uint it = sBlock[k0 + g];
            updateHiz(uvec2((it >> 6) & 0x1FFFu, it >> 19), sBlockMax[g]);
          }
        barrier();
      }
      barrier();
      if (sPending == 0u) break;
    }
  }
  barrier();
  if (lid == 0u) sQueueCount = 0u;
}

void main() {
  const uint lid = gl_LocalInvocationID.x;
  if (lid == 0u) {
    sTop = 1u;
    sStack[0] = uvec2(0u, packRect(frustumOrigin(), FRUSTUM_LOG2));
    sQueueCount = 0u;
  }
  // A HiZ entry none of whose pixels is on screen starts at 0 (nothing to wait for), the others
  // at kNoDepth.
  if (HIZ) {
    uint offset = 0u;
    for (uint l = 0u; l <= FRUSTUM_LOG2; ++l) {
      const uint side = 1u << (FRUSTUM_LOG2 - l);
      for (uint i = lid; i < side * side; i += gl_WorkGroupSize.x) {
        const uvec2 o = frustumOrigin() + uvec2(i % side, i / side) * (8u << l);
        sHiz[offset + i] = o.x < r3.width && o.y < r3.height ? kNoDepth : 0u;
      }
      offset += side * side;
    }
  }
  Work work = Work(0u, 0u, 0u, 0u, 0u, 0u, 0u);
  Tally tally = Tally(0u, 0u, 0u, 0u);
  barrier();
  while (true) {
    const uint top = sTop;
    if (top == 0u) break;  // uniform: read by every thread after the barrier
    const uint n = min(top, 64u);
    const bool have = lid < n;
    uvec2 entry = uvec2(0u);
    if (have) entry = sStack[top - n + lid];
    barrier();
    if (lid == 0u) sTop = top - n;
    barrier();
    if (have) visit(entry, work, tally);
    barrier();
    if (lid == 0u) sTop = min(sTop, min(kStack, STACK_LIMIT));
    if (sQueueCount > 0u) rasterizeQueue(work, tally);  // uniform
    barrier();
  }
  if (ANALYSIS == 1) {
    if (lid == 0u) atomicAdd(counters[kR3dCounterFrusta], 1ul);
    atomicAdd(counters[kR3dCounterNodes], uint64_t(work.nodes));
    atomicAdd(counters[kR3dCounterSplits], uint64_t(work.splits));
    atomicAdd(counters[kR3dCounterCulledFrustum], uint64_t(work.culledFrustum));
    atomicAdd(counters[kR3dCounterCulledOcclusion], uint64_t(work.culledOcclusion));
    atomicAdd(counters[kR3dCounterCulledEarlyZ], uint64_t(work.earlyZ));
    atomicAdd(counters[kR3dCounterStackOverflows], uint64_t(work.overflows));
    atomicAdd(counters[kR3dCounterSetups], uint64_t(work.setups));
  }
  flush(tally);
}
