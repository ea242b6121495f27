#version 460
// Photon splatting in compute (splat=compute; effects/indirect/indirect_pass.cpp recordSplatInto):
// a 256-thread group per 16x16 tile, a thread per pixel. The tile's coarse bin lists, in slot order,
// the slots whose footprint's box may reach it (photon_splat_bin.comp.glsl). The group takes them 256
// at a time: each thread tests one slot's pixel box against the tile, the ones that reach it are
// packed in shared memory in slot order (a subgroup ballot's prefix) with their quad's projected
// corners, and every pixel then adds, in that order, the irradiance of each photon whose quad covers
// its centre (the raster splat's coverage: photon_splat.vert.glsl draws that quad) at its own surface
// point (photon_splat.glsl.inc, the raster splat's fragment stage's own expression). So each pixel
// sums the same terms in the same order as the raster splat's additive blending, and the result is
// deterministic. Differences from the raster splat: a pixel centre on the quad's edge counts here
// (the rasterizer's top-left rule and sub-pixel snapping decide it there), and a quad with a corner
// behind the eye, which the rasterizer clips, covers every pixel here, its ellipse alone deciding.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_ballot : require
#include "surface_constants.glsl.inc"
layout(local_size_x = 16, local_size_y = 16) in;

#include "surface.glsl.inc"

#include "depth_texel.glsl.inc"
layout(set = 0, binding = HB_INDIRECT_PHOTONS) readonly buffer Photons { Photon photons[]; };
layout(set = 0, binding = HB_INDIRECT_IRRADIANCE, rgba32f) uniform writeonly image2D irradianceImage;
layout(set = 1, binding = HB_SPLAT_BOXES) readonly buffer Boxes { uvec2 boxes[]; };
layout(set = 1, binding = HB_SPLAT_BINS) readonly buffer Bins { uvec4 bins[]; };
layout(set = 1, binding = HB_SPLAT_LIST) readonly buffer List { uint list[]; };
layout(push_constant) uniform Push { SplatConstants sc; };
#include "photon_splat.glsl.inc"

float depthAt(ivec2 p) { return fetchDepth(p); }

shared Photon sPhotons[256];
shared vec4 sCorners[256][2];  // the quad's corners in pixels: (c0, c1), (c2, c3)
shared uint sBehind[256];      // 1: a corner behind the eye, no coverage test
shared uint sTotals[256];

// Whether pixel centre q lies in the convex quad c0 c1 c2 c3 (either winding; on an edge counts).
bool covers(vec4 c01, vec4 c23, vec2 q) {
  const vec2 c[4] = vec2[](c01.xy, c01.zw, c23.xy, c23.zw);
  bool pos = true, neg = true;
  for (uint i = 0u; i < 4u; ++i) {
    const vec2 a = c[i], d = c[(i + 1u) & 3u] - a, r = q - a;
    const float e = d.x * r.y - d.y * r.x;
    pos = pos && e >= 0.0;
    neg = neg && e <= 0.0;
  }
  return pos != neg;  // both: a quad of no area, which the rasterizer draws nothing of
}

void main() {
  const uvec2 tile = gl_WorkGroupID.xy;
  const ivec2 p = ivec2(tile * kSplatTile + gl_LocalInvocationID.xy);
  const bool inside = p.x < int(frame.extent.x) && p.y < int(frame.extent.y);
  const bool receives = inside && hasDepth(p);
  vec3 y = vec3(0.0), ny = vec3(0.0);
  if (receives) {
    y = worldPos(p);
    ny = NORMALS == kNormalsGeometric ? geometricNormal(p, y) : reconstructNormal(p, y);
  }
  const uvec2 bin = tile * kSplatTile / sc.binPixels;
  const uvec4 range = bins[bin.y * sc.binsX + bin.x];
  const bool listed = range.z != 0u;  // else the list ran out: every slot, in order
  const uint entries = listed ? range.y : sc.slots;
  const uvec2 t0 = tile * kSplatTile, t1 = t0 + kSplatTile - 1u;
  const uint e = gl_SubgroupID * gl_SubgroupSize + gl_SubgroupInvocationID;  // the entry it tests
  const vec2 q = vec2(p) + 0.5;
  vec3 sum = vec3(0.0);
  for (uint base = 0u; base < entries; base += 256u) {
    uint slot = 0u;
    bool hit = false;
    if (base + e < entries) {
      slot = listed ? list[range.x + base + e] : base + e;
      const uvec2 bx = boxes[slot];
      const uvec2 a = uvec2(bx.x & 0xFFFFu, bx.x >> 16), b = uvec2(bx.y & 0xFFFFu, bx.y >> 16);
      hit = a.x <= t1.x && b.x >= t0.x && a.y <= t1.y && b.y >= t0.y;
    }
    const uvec4 ballot = subgroupBallot(hit);
    if (subgroupElect()) sTotals[gl_SubgroupID] = subgroupBallotBitCount(ballot);
    barrier();
    uint before = 0u, n = 0u;
    for (uint g = 0u; g < gl_NumSubgroups; ++g) {
      const uint v = sTotals[g];
      before += g < gl_SubgroupID ? v : 0u;
      n += v;
    }
    if (hit) {
      const uint at = before + subgroupBallotExclusiveBitCount(ballot);
      const Photon ph = photons[slot];
      sPhotons[at] = ph;
      vec2 c[4];
      bool behind = false;
      for (uint k = 0u; k < 4u; ++k) {  // photon_splat.vert.glsl's corners, in its order around the quad
        const vec2 corner = vec2((k == 1u || k == 2u) ? 0.5 : -0.5, k >= 2u ? 0.5 : -0.5);
        const vec4 clip =
            frame.viewProj * vec4(ph.positionFluxR.xyz + corner.x * ph.duFluxG.xyz + corner.y * ph.dvFluxB.xyz, 1.0);
        behind = behind || !(clip.w > 0.0);
        c[k] = (clip.xy / clip.w * 0.5 + 0.5) * frame.extent.xy;
      }
      sCorners[at][0] = vec4(c[0], c[1]);
      sCorners[at][1] = vec4(c[2], c[3]);
      sBehind[at] = behind ? 1u : 0u;
    }
    memoryBarrierShared();
    barrier();
    if (receives)
      for (uint j = 0u; j < n; ++j) {
        vec3 ej;
        if ((sBehind[j] != 0u || covers(sCorners[j][0], sCorners[j][1], q)) && splatIrradiance(sPhotons[j], y, ny, ej))
          sum += ej;
      }
    barrier();
  }
  if (inside) imageStore(irradianceImage, p, vec4(sum, 0.0));
}
