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
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_explicit_arithmetic_types_float64 : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_buffer_reference : require
#include "shared/gpu_types.h"
#include "shared/bindings.h"

layout(constant_id = 0) const uint RESOLUTION = 128;
layout(constant_id = 1) const uint NODE_CAPACITY = 1;
layout(constant_id = 2) const uint PIXELS = 1;  // maps × RESOLUTION²
layout(constant_id = 3) const uint LIST = kLdmListMax64;
layout(constant_id = 4) const uint PHASE = kLdmPhaseInsert;
layout(local_size_x = 64) in;

layout(set = 0, binding = HB_LDM_MAPS) readonly buffer Maps { LdmMap maps[]; };
layout(set = 0, binding = HB_LDM_LINKS_ADDRESS) uniform LinksAddress { uvec2 linksAddress; };  // gpu_types.h layouts
layout(set = 0, binding = HB_LDM_COUNTERS) buffer Counters { uint counters[]; };
layout(set = 0, binding = HB_LDM_TRIANGLES) readonly buffer Triangles { vec4 triVerts[]; };  // 3 per triangle, world space
layout(push_constant) uniform Push { uint triangleCount; };

#include "ldm_insert.glsl.inc"

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

void main() {
  const uint tri = gl_GlobalInvocationID.x, map = gl_GlobalInvocationID.y;
  if (tri >= triangleCount) return;
  const LdmMap m = maps[map];
  const float r = m.centreRadius.w, halfRes = 0.5 * float(RESOLUTION);
  vec2 p[3];
  float z[3];
  for (int k = 0; k < 3; ++k) {
    const vec3 q = triVerts[3u * tri + uint(k)].xyz - m.centreRadius.xyz;
    // Pixel coordinates with pixel centres at integers (gpu_types.h LdmMap).
    p[k] = vec2((dot(q, m.right.xyz) / r + 1.0) * halfRes - 0.5, (1.0 - dot(q, m.up.xyz) / r) * halfRes - 0.5);
    z[k] = dot(q, m.dir.xyz) + r;
  }
  precise float area = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[1].y - p[0].y) * (p[2].x - p[0].x);
  if (!(area != 0.0)) return;  // degenerate in this view (also NaN)
  const float o = area > 0.0 ? -1.0 : 1.0;  // makes every edge function positive inside
  const bool own0 = owns(p[1], p[2], o), own1 = owns(p[2], p[0], o), own2 = owns(p[0], p[1], o);
  const ivec2 lo = max(ivec2(ceil(min(p[0], min(p[1], p[2])))), ivec2(0));
  const ivec2 hi = min(ivec2(floor(max(p[0], max(p[1], p[2])))), ivec2(int(RESOLUTION) - 1));
  for (int y = lo.y; y <= hi.y; ++y)
    for (int x = lo.x; x <= hi.x; ++x) {
      const vec2 c = vec2(x, y);
      const float e0 = o * edge(p[1], p[2], c), e1 = o * edge(p[2], p[0], c), e2 = o * edge(p[0], p[1], c);
      if (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) continue;
      if ((e0 == 0.0 && !own0) || (e1 == 0.0 && !own1) || (e2 == 0.0 && !own2)) continue;
      const float sum = e0 + e1 + e2;
      const float depth = (e0 * z[0] + e1 * z[1] + e2 * z[2]) / sum;
      const uint pixel = (map * RESOLUTION + uint(y)) * RESOLUTION + uint(x);
      if (LIST == kLdmListSbuffer) {
        ldmSbuffer(linksAddress, pixel, depth, tri);
        continue;
      }
      const uint node = atomicAdd(counters[kLdmCounterAllocated], 1u) + 1u;
      if (node > NODE_CAPACITY) {
        atomicAdd(counters[kLdmCounterOverflow], 1u);
        continue;
      }
      ldmInsert(linksAddress, pixel, node, depth);
    }
}
