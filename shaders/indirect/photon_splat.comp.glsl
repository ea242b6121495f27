#version 460
// Photon splatting in compute (splat=compute; effects/indirect/indirect_pass.cpp recordSplatInto):
// a 256-thread group per 16x16 tile, a thread per pixel. The tile's coarse bin lists, in slot order,
// the slots whose footprint's box may reach it (photon_splat_bin.comp.glsl). The group takes them 128
// at a time: a thread tests one slot's pixel box against the tile, and the photons that reach it are
// packed in shared memory in slot order (a subgroup ballot's prefix), with what depends on the photon
// alone (photon_splat.glsl.inc splatSetup) and the edges of its quad projected to pixels. Every pixel
// then adds, in that order, the irradiance of each photon whose quad covers its centre (the raster
// splat's coverage: photon_splat.vert.glsl draws that quad) at its own surface point (splatAt, the
// raster splat's fragment stage's own expressions, set up per photon here). So each pixel
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
readonly buffer Photons { Photon photons[]; };
layout(rgba32f) uniform writeonly image2D irradianceImage;
readonly buffer Boxes { uvec2 boxes[]; };
readonly buffer Bins { uvec4 bins[]; };
readonly buffer List { uint list[]; };
layout(push_constant) uniform Push { SplatConstants sc; };
#include "photon_splat.glsl.inc"
#include "splat_append.glsl.inc"

float depthAt(ivec2 p) { return fetchDepth(p); }

// A round's photons that reach the tile, in slot order: their setup (photon_splat.glsl.inc) and
// their quad's four edges in pixels, A·x + B·y + C >= 0 inside (oriented so; a quad with a corner
// behind the eye gets edges that hold every pixel).
const uint kRound = 128u;  // entries a round: 120 B of shared memory each, 15 KiB in all
shared vec4 sX[kRound], sN[kRound], sDvn[kRound], sNdu[kRound];
shared vec2 sFlux[kRound];
shared vec4 sEdgeA[kRound], sEdgeB[kRound], sEdgeC[kRound];  // component k: edge k's A, B, C

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
  for (uint base = 0u; base < entries; base += kRound) {
    uint slot = 0u;
    bool hit = false;
    if (e < kRound && base + e < entries) {
      slot = listed ? list[range.x + base + e] : base + e;
      const uvec2 bx = boxes[slot];
      const uvec2 a = uvec2(bx.x & 0xFFFFu, bx.x >> 16), b = uvec2(bx.y & 0xFFFFu, bx.y >> 16);
      hit = a.x <= t1.x && b.x >= t0.x && a.y <= t1.y && b.y >= t0.y;
    }
    // The photon's setup and its quad's edges; a footprint or quad of no area gives nothing (the
    // rasterizer draws nothing of a quad of no area).
    SplatSetup sp;
    vec4 ea = vec4(0.0), eb = vec4(0.0), ec = vec4(1.0);
    if (hit) {
      const Photon ph = photons[slot];
      hit = splatSetup(ph, sp);
      vec2 c[4];
      bool behind = false;
      for (uint k = 0u; k < 4u; ++k) {  // photon_splat.vert.glsl's corners, in its order around the quad
        const vec2 corner = vec2((k == 1u || k == 2u) ? 0.5 : -0.5, k >= 2u ? 0.5 : -0.5);
        const vec4 clip =
            frame.viewProj * vec4(ph.positionFluxR.xyz + corner.x * ph.duFluxG.xyz + corner.y * ph.dvFluxB.xyz, 1.0);
        behind = behind || !(clip.w > 0.0);
        c[k] = (clip.xy / clip.w * 0.5 + 0.5) * frame.extent.xy;
      }
      if (!behind) {
        float twiceArea = 0.0;
        for (uint k = 0u; k < 4u; ++k) {
          const vec2 from = c[k], d = c[(k + 1u) & 3u] - from;
          ea[k] = -d.y;
          eb[k] = d.x;
          ec[k] = d.y * from.x - d.x * from.y;
          twiceArea += from.x * c[(k + 1u) & 3u].y - c[(k + 1u) & 3u].x * from.y;
        }
        hit = hit && twiceArea != 0.0;
        const float orient = twiceArea < 0.0 ? -1.0 : 1.0;
        ea *= orient;
        eb *= orient;
        ec *= orient;
      }
    }
    uint n;
    const uint at = appendPlace(hit, n);
    if (hit) {
      sX[at] = sp.xScale;
      sN[at] = sp.nRoot;
      sDvn[at] = sp.dvnArea;
      sNdu[at] = sp.nduR;
      sFlux[at] = sp.fluxGB;
      sEdgeA[at] = ea;
      sEdgeB[at] = eb;
      sEdgeC[at] = ec;
    }
    memoryBarrierShared();
    barrier();
    if (receives)
      for (uint j = 0u; j < n; ++j) {
        const vec4 cover = sEdgeA[j] * q.x + sEdgeB[j] * q.y + sEdgeC[j];
        if (any(lessThan(cover, vec4(0.0)))) continue;
        const SplatSetup s = SplatSetup(sX[j], sN[j], sDvn[j], sNdu[j], sFlux[j]);
        vec3 ej;
        if (splatAt(s, y, ny, ej)) sum += ej;
      }
    barrier();
  }
  if (inside) imageStore(irradianceImage, p, vec4(sum, 0.0));
}
