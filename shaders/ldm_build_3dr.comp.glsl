#version 460
// Layered depth maps, the compute build (ldm_build=3dr): 3D rasterization in orthographic mode
// (Davidovič et al. 2012, Sect. 3.3) over every (triangle, map) pair, one thread each, instead of
// the raster hardware (which the H100/H200 have little of). For a parallel view along dir the 3D
// edge function V_i = (m_i − o)·(e_i × dir) of a pixel's line o is the 2D edge function in the
// map's plane, written here in pixel units in the midpoint form m_i = (a + b)/2, e_i = b − a, so
// that two triangles sharing an edge evaluate bitwise opposite values (the paper's consistency);
// a pixel centre exactly on an edge goes to the triangle whose edge is a top or left one (the
// edge derivatives' signs, Sect. 3.4). Depth: the barycentric blend of the vertices' depths
// z = (p − c)·dir + r with weights V_i/ΣV. An edge value within its rounding bound of zero is
// decided in double (below), so centres at shared vertices go to exactly one triangle. Each covered pixel inserts as the fragment shader does (ldm_insert.glsl.inc).
//
// Balance (MODE): one thread a (triangle, map) pair leaves a subgroup waiting on its largest box
// (on the atrium 84 % of pairs hold no pixel centre, a few hold thousands, and a serial fill loop
// waits on an atomic's return for every fragment). So MODE 0 (pairs) rasterizes a pair itself only
// when its box holds at most SMALL_BOX centres (kLdmSmallBox); a larger pair is listed as chunks of
// CHUNK_PIXELS (kLdmChunk) pixels of its box in row order (gpu_types.h kLdmCounterChunks), and
// MODE 1 (chunks) gives each chunk a workgroup of 64 threads, each testing CHUNK_PIXELS / 64 of its
// pixels. Both modes compute a pair's view with the same `precise` expressions (no contraction), so
// a pixel gets the same edge values, owner and depth whichever mode rasterizes its triangle. A full
// chunk list is counted (kLdmCounterChunkOverflow) and the pair rasterized by its own thread.
// Measured on the H200 (docs/methods/layered-depth-maps.md "The compute build"): 8x8 tiles of one
// pixel a thread, a setup in shared memory, 256-pixel chunks and several maps a thread were slower.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_explicit_arithmetic_types_float64 : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_buffer_reference : require
#include "shared/gpu_types.h"

#include "ldm_build_constants.glsl.inc"
layout(constant_id = 5) const uint MODE = 0u;  // 0: a thread a pair, 1: a workgroup a listed chunk
layout(constant_id = 6) const uint SMALL_BOX = kLdmSmallBox;
layout(constant_id = 7) const uint CHUNK_CAPACITY = 1;
layout(constant_id = 8) const uint CHUNK_PIXELS = kLdmChunk;  // a multiple of 64
layout(local_size_x = 64) in;

readonly buffer Maps { LdmMap maps[]; };
uniform LinksAddress { uvec2 linksAddress; };  // gpu_types.h layouts
buffer Counters { uint counters[]; };
readonly buffer Triangles { vec4 triVerts[]; };  // 3 per triangle, world space
buffer Chunks { uvec2 chunks[]; };
layout(push_constant) uniform Push { uint triangleCount; };

#include "ldm_insert.glsl.inc"

const uint CHUNK_COUNTER = PHASE == kLdmPhaseFill ? kLdmCounterChunksFill : kLdmCounterChunks;
const uint kNoChunk = 0xFFFFFFFFu;  // a chunk entry of a pair that did not fit the list

// Edge (a → b) at pixel centre q, midpoint form: (q − m) × e with m = (a + b)/2, e = b − a.
// Its rounding (derived like 3DR's, raster3d.glsl.inc): m errs by u|m|, q − m by u(|q| + |m|) more,
// e by u|e|, the two products and the difference by u each, so |v − v(exact on the float inputs)|
// <= 6u·mag (1 + O(u)) with mag = (|q.x| + |m.x|)|e.y| + (|q.y| + |m.y|)|e.x|. Within 16u·mag of
// zero the sign is decided by the same expression in double from the same float inputs (2^29 times
// smaller error: exact for these magnitudes), 3DR's fp64 fallback: so two triangles sharing a
// vertex agree on which owns a centre on their edges, not only those sharing the edge.
float edge(vec2 a, vec2 b, vec2 q) {
  precise vec2 m = (a + b) * 0.5;
  precise vec2 e = b - a;
  precise float t1 = (q.x - m.x) * e.y;
  precise float t2 = (q.y - m.y) * e.x;
  precise float v = t1 - t2;
  const float mag = (abs(q.x) + abs(m.x)) * abs(e.y) + (abs(q.y) + abs(m.y)) * abs(e.x);
  if (abs(v) <= 16.0 * 5.9604644775390625e-8 * mag) {
    const dvec2 da = dvec2(a), db = dvec2(b), dq = dvec2(q);
    const dvec2 dm = (da + db) * 0.5LF, de = db - da;
    const double dv = (dq.x - dm.x) * de.y - (dq.y - dm.y) * de.x;
    atomicAdd(counters[kLdmCounterFp64], 1u);
    return float(dv);  // a float too small for its sign is 0: then the tie rule decides, alike for both
  }
  return v;
}

// The top-left rule from the edge's derivatives (Sect. 3.4): a centre exactly on the edge belongs
// to the triangle for which the edge function grows to the right (∂V/∂x > 0), or, for a
// horizontal edge, grows downwards (∂V/∂y > 0). Of two triangles sharing the edge exactly one
// sees that.
bool owns(vec2 a, vec2 b, float orientation) {
  const float dx = orientation * (b.y - a.y), dy = -orientation * (b.x - a.x);
  return dx > 0.0 || (dx == 0.0 && dy > 0.0);
}

// A triangle in one map: its vertices in pixel coordinates (pixel centres at integers: gpu_types.h
// LdmMap), their depths, the orientation that makes every edge value positive inside, the top-left
// ownership of each edge, and the box of pixel centres it may cover.
struct Pair {
  vec2 p[3];
  float z[3];
  float o;
  bool own[3];
  ivec2 lo, hi;
};

void loadTriangle(uint tri, out vec3 v[3]) {
  for (int k = 0; k < 3; ++k) v[k] = triVerts[3u * tri + uint(k)].xyz;
}

// False for a triangle degenerate in this view (also NaN) or whose box holds no pixel centre.
bool setupPair(const vec3 v[3], uint map, out Pair s) {
  const LdmMap m = maps[map];
  const float r = m.centreRadius.w, halfRes = 0.5 * float(RESOLUTION);
  for (int k = 0; k < 3; ++k) {
    precise vec3 q = v[k] - m.centreRadius.xyz;
    precise float x = q.x * m.right.x + q.y * m.right.y + q.z * m.right.z;
    precise float y = q.x * m.up.x + q.y * m.up.y + q.z * m.up.z;
    precise float z = q.x * m.dir.x + q.y * m.dir.y + q.z * m.dir.z;
    precise vec2 p = vec2((x / r + 1.0) * halfRes - 0.5, (1.0 - y / r) * halfRes - 0.5);
    precise float depth = z + r;
    s.p[k] = p;
    s.z[k] = depth;
  }
  precise float area = (s.p[1].x - s.p[0].x) * (s.p[2].y - s.p[0].y) - (s.p[1].y - s.p[0].y) * (s.p[2].x - s.p[0].x);
  if (!(area != 0.0)) return false;
  s.o = area > 0.0 ? -1.0 : 1.0;
  s.own[0] = owns(s.p[1], s.p[2], s.o);
  s.own[1] = owns(s.p[2], s.p[0], s.o);
  s.own[2] = owns(s.p[0], s.p[1], s.o);
  s.lo = max(ivec2(ceil(min(s.p[0], min(s.p[1], s.p[2])))), ivec2(0));
  s.hi = min(ivec2(floor(max(s.p[0], max(s.p[1], s.p[2])))), ivec2(int(RESOLUTION) - 1));
  return all(lessThanEqual(s.lo, s.hi));
}

// Pixel centre c of the pair's box: inserted when the triangle covers it.
void rasterPixel(const Pair s, uint tri, uint map, ivec2 c) {
  const vec2 q = vec2(c);
  const float e0 = s.o * edge(s.p[1], s.p[2], q), e1 = s.o * edge(s.p[2], s.p[0], q),
              e2 = s.o * edge(s.p[0], s.p[1], q);
  if (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) return;
  if ((e0 == 0.0 && !s.own[0]) || (e1 == 0.0 && !s.own[1]) || (e2 == 0.0 && !s.own[2])) return;
  precise float sum = e0 + e1 + e2;
  precise float depth = (e0 * s.z[0] + e1 * s.z[1] + e2 * s.z[2]) / sum;
  const uint pixel = (map * RESOLUTION + uint(c.y)) * RESOLUTION + uint(c.x);
  if (LIST == kLdmListSbuffer) {
    ldmSbuffer(linksAddress, pixel, depth, tri);
    return;
  }
  const uint node = atomicAdd(counters[kLdmCounterAllocated], 1u) + 1u;
  if (node > NODE_CAPACITY) {
    atomicAdd(counters[kLdmCounterOverflow], 1u);
    return;
  }
  ldmInsert(linksAddress, pixel, node, depth);
}

// MODE 0: a thread per (triangle, map) pair.
void pairs() {
  const uint tri = gl_GlobalInvocationID.x, map = gl_GlobalInvocationID.y;
  if (tri >= triangleCount) return;
  vec3 v[3];
  loadTriangle(tri, v);
  Pair s;
  if (!setupPair(v, map, s)) return;
  const uvec2 size = uvec2(s.hi - s.lo) + 1u;
  if (size.x * size.y > SMALL_BOX) {
    const uint count = (size.x * size.y + CHUNK_PIXELS - 1u) / CHUNK_PIXELS;
    const uint base = atomicAdd(counters[CHUNK_COUNTER], count);
    const bool fits = base < CHUNK_CAPACITY && count <= CHUNK_CAPACITY - base;
    for (uint t = 0u; t < count && base + t < CHUNK_CAPACITY; ++t)
      chunks[base + t] = fits ? uvec2(tri, map | t << 11) : uvec2(kNoChunk, 0u);
    if (fits) return;
    atomicAdd(counters[kLdmCounterChunkOverflow], 1u);
  }
  for (int y = s.lo.y; y <= s.hi.y; ++y)
    for (int x = s.lo.x; x <= s.hi.x; ++x) rasterPixel(s, tri, map, ivec2(x, y));
}

// MODE 1: the listed chunks, a workgroup each (grid-stride over the list); each thread sets the pair
// up itself and tests CHUNK_PIXELS / 64 pixels of the chunk, 64 apart (neighbouring threads,
// neighbouring pixels), so that one setup serves several pixels.
void listedChunks() {
  const uint listed = min(counters[CHUNK_COUNTER], CHUNK_CAPACITY);
  for (uint e = gl_WorkGroupID.x; e < listed; e += gl_NumWorkGroups.x) {
    const uvec2 entry = chunks[e];
    if (entry.x == kNoChunk) continue;
    const uint map = entry.y & 0x7FFu;
    vec3 v[3];
    loadTriangle(entry.x, v);
    Pair s;
    if (!setupPair(v, map, s)) continue;  // never: it was listed
    const uint w = uint(s.hi.x - s.lo.x) + 1u, area = w * (uint(s.hi.y - s.lo.y) + 1u);
    const uint first = (entry.y >> 11) * CHUNK_PIXELS + gl_LocalInvocationIndex;
    for (uint k = 0u; k < CHUNK_PIXELS / 64u; ++k) {
      const uint i = first + 64u * k;
      if (i < area) rasterPixel(s, entry.x, map, s.lo + ivec2(i % w, i / w));
    }
  }
}

void main() {
  if (MODE == 0u)
    pairs();
  else
    listedChunks();
}
