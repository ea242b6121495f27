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
// later_bounce_stride f > 1 (indirect_pass.cpp recordComputeSplat): the later bounces' slots are
// splatted first, at one receiver a f x f block (STRIDE = f: the block's pixel i·f + f/2, its
// own surface point and coverage at its own centre, so a receiver's value is the full splat's sum of
// those terms) into lateIrradiance; then the first bounce's slots at every pixel (STRIDE = 1, LATE = f), and
// each pixel adds the later bounces interpolated from the receivers on its own surface (lateAt).
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_ballot : require
#include "surface_constants.glsl.inc"
layout(local_size_x = 16, local_size_y = 16) in;

#include "surface.glsl.inc"

#include "depth_texel.glsl.inc"
readonly buffer Photons { Photon photons[]; };
layout(rgba32f) uniform writeonly image2D irradianceImage;
layout(rgba32f) uniform image2D lateIrradiance;  // the later bounces at the receivers (1x1 unless f > 1)
// COUNT (analysis frames): each tile writes its receivers' coverage tests (a photon of the round
// against the pixel's centre) and terms (covered, facing, inside the ellipse) to work[sc.workBase +
// its index], the gather's real work for the roofline (effects/indirect/indirect_part.cpp).
layout(constant_id = 2) const uint COUNT = 0u;
// The receivers: a pixel in STRIDE x STRIDE; LATE > 1: add lateIrradiance, splatted at that stride.
// Constants, so the default gather (1, 1) compiles to the code without either.
layout(constant_id = 3) const uint STRIDE = 1u;
layout(constant_id = 4) const uint LATE = 1u;
// The later bounces' run splits each tile's list into PARTS parts, a workgroup each (gl_WorkGroupID.z),
// so that a coarse image of few tiles still fills the device. Part z's sums are rows z·(its height)
// of lateIrradiance; lateAt adds the parts in order, so the sum stays deterministic.
layout(constant_id = 5) const uint PARTS = 1u;
buffer SplatWork { uvec2 work[]; };
shared uint sTests, sTerms;
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

vec3 normalAt(ivec2 p, vec3 y) { return NORMALS == kNormalsGeometric ? geometricNormal(p, y) : reconstructNormal(p, y); }

// Stride f: receiver i of the later bounces is pixel i·f + f/2, clamped to the image.
ivec2 receiverOf(ivec2 i, int f) { return min(i * f + f / 2, ivec2(frame.extent.xy) - 1); }

// Whether receiver r lies on the surface of pixel y (normal ny): facing within ~25.8° (cos 0.9) and
// off y's tangent plane by at most 1/20 of their distance (a slope of 2.9°). Float depth gives a
// flat wall's points a few 1e-7 off its plane relative to their distance, far inside; a corner's
// two walls (cos 0) and a step in depth fail it.
const float kLateCos = 0.9, kLateSlope = 0.05;
bool sameSurface(ivec2 r, vec3 y, vec3 ny) {
  if (!hasDepth(r)) return false;
  const vec3 yr = worldPos(r);
  return dot(normalAt(r, yr), ny) > kLateCos && abs(dot(ny, yr - y)) <= kLateSlope * length(yr - y);
}

// Receiver i's later light: its parts' sums, in order (rows: the coarse image's height).
vec3 lateValue(ivec2 i, int rows) {
  vec3 v = imageLoad(lateIrradiance, i).rgb;
  for (int z = 1; z < int(PARTS); ++z) v += imageLoad(lateIrradiance, i + ivec2(0, z * rows)).rgb;
  return v;
}

// The later bounces at pixel p: the bilinear weights of the four receivers around it, over those on
// its own surface (at a receiver itself, its value alone). Where none of the four is, the nearest
// of the 4x4 around it that is; where none is, nothing (a sliver narrower than the stride).
vec3 lateAt(ivec2 p, vec3 y, vec3 ny) {
  const int f = int(LATE);
  const ivec2 cext = (ivec2(frame.extent.xy) + f - 1) / f;
  const vec2 u = (vec2(p) - float(f / 2)) / float(f);
  const ivec2 i0 = ivec2(floor(u));
  const vec2 w = u - vec2(i0);
  vec3 acc = vec3(0.0);
  float wsum = 0.0;
  for (int k = 0; k < 4; ++k) {
    const ivec2 i = i0 + ivec2(k & 1, k >> 1);
    const float wb = ((k & 1) != 0 ? w.x : 1.0 - w.x) * ((k >> 1) != 0 ? w.y : 1.0 - w.y);
    if (!(wb > 0.0) || any(lessThan(i, ivec2(0))) || any(greaterThanEqual(i, cext))) continue;
    if (!sameSurface(receiverOf(i, f), y, ny)) continue;
    acc += wb * lateValue(i, cext.y);
    wsum += wb;
  }
  if (wsum > 0.0) return acc / wsum;
  float best = 1e30;
  vec3 nearest = vec3(0.0);
  for (int k = 0; k < 16; ++k) {
    const ivec2 i = i0 + ivec2(k & 3, k >> 2) - 1;
    if (any(lessThan(i, ivec2(0))) || any(greaterThanEqual(i, cext))) continue;
    const ivec2 r = receiverOf(i, f);
    const vec2 d = vec2(r - p);
    if (dot(d, d) < best && sameSurface(r, y, ny)) {
      best = dot(d, d);
      nearest = lateValue(i, cext.y);
    }
  }
  return nearest;
}

void main() {
  const uvec2 tile = gl_WorkGroupID.xy;
  // This run's receivers: every pixel (stride 1), or pixel i·f + f/2 of each f x f block.
  const int f = int(STRIDE);
  const ivec2 pc = ivec2(tile * kSplatTile + gl_LocalInvocationID.xy);
  const ivec2 p = f == 1 ? pc : receiverOf(pc, f);
  const bool inside = all(lessThan(pc, (ivec2(frame.extent.xy) + f - 1) / f));
  const bool receives = inside && hasDepth(p);
  vec3 y = vec3(0.0), ny = vec3(0.0);
  if (receives) {
    y = worldPos(p);
    ny = normalAt(p, y);
  }
  // The tile's pixels (f x f blocks of them), within one bin: kSplatTile·f divides binPixels.
  const uvec2 t0 = tile * kSplatTile * uint(f), t1 = t0 + kSplatTile * uint(f) - 1u;
  const uvec2 bin = t0 / sc.binPixels;
  const uvec4 range = bins[bin.y * sc.binsX + bin.x];
  const bool listed = range.z != 0u;  // else the list ran out: every slot of the run, in order
  const uint entries = listed ? range.y : sc.slots;
  // This workgroup's part of them (the later bounces' run: PARTS; the first bounce's: all).
  const uint parts = STRIDE > 1u ? PARTS : 1u;
  const uint per = (entries + parts - 1u) / parts, begin = min(gl_WorkGroupID.z * per, entries),
             end = min(begin + per, entries);
  const uint e = gl_SubgroupID * gl_SubgroupSize + gl_SubgroupInvocationID;  // the entry it tests
  const vec2 q = vec2(p) + 0.5;
  vec3 sum = vec3(0.0);
  uint tests = 0u, terms = 0u;
  if (COUNT != 0u) {
    if (gl_LocalInvocationIndex == 0u) sTests = sTerms = 0u;
    barrier();
  }
  for (uint base = begin; base < end; base += kRound) {
    uint slot = 0u;
    bool hit = false;
    if (e < kRound && base + e < end) {
      slot = listed ? list[range.x + base + e] : sc.first + base + e;
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
        // A quad that misses every pixel centre of the tile adds nothing there: dropped before the
        // pixels test it (a needle's box reaches many tiles its quad misses). Edge k is linear, so its
        // largest value over the tile's centres is at a corner of their rectangle; below −margin
        // there, every centre is outside edge k. The margin, 1e-5 of |A|·x + |B|·y + |C| at the far
        // corner (coordinates are >= 0), is far beyond float's rounding of both evaluations (a few
        // u of that sum each), so no centre the pixels would count is dropped: the sums are the same.
        const vec2 lo = vec2(t0) + 0.5, hi = vec2(t1) + 0.5;
        const vec4 xs = mix(vec4(lo.x), vec4(hi.x), greaterThan(ea, vec4(0.0)));
        const vec4 ys = mix(vec4(lo.y), vec4(hi.y), greaterThan(eb, vec4(0.0)));
        const vec4 best = ea * xs + eb * ys + ec, scale = abs(ea) * hi.x + abs(eb) * hi.y + abs(ec);
        if (any(lessThan(best, -1e-5 * scale))) hit = false;
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
    if (receives) {
      if (COUNT != 0u) tests += n;
      for (uint j = 0u; j < n; ++j) {
        const vec4 cover = sEdgeA[j] * q.x + sEdgeB[j] * q.y + sEdgeC[j];
        if (any(lessThan(cover, vec4(0.0)))) continue;
        const SplatSetup s = SplatSetup(sX[j], sN[j], sDvn[j], sNdu[j], sFlux[j]);
        vec3 ej;
        if (splatAt(s, y, ny, ej)) {
          sum += ej;
          if (COUNT != 0u) ++terms;
        }
      }
    }
    barrier();
  }
  if (COUNT != 0u) {
    atomicAdd(sTests, tests);
    atomicAdd(sTerms, terms);
    barrier();
    if (gl_LocalInvocationIndex == 0u)
      work[sc.workBase + (gl_WorkGroupID.z * gl_NumWorkGroups.y + gl_WorkGroupID.y) * gl_NumWorkGroups.x +
           gl_WorkGroupID.x] = uvec2(sTests, sTerms);
  }
  if (f > 1) {
    const int rows = (int(frame.extent.y) + f - 1) / f;
    if (inside) imageStore(lateIrradiance, pc + ivec2(0, int(gl_WorkGroupID.z) * rows), vec4(sum, 0.0));
    return;
  }
  if (LATE > 1u && receives) sum += lateAt(p, y, ny);
  if (inside) imageStore(irradianceImage, p, vec4(sum, 0.0));
}
