#version 460
// Pass 3 (thesis 4.2.3): tiled light culling, gather approach, one workgroup per tile. Mirrors
// cull_ref.h (tileDepthRange, tileVolume, lightTouchesTile, cullTile) op for op via culling.glsl.inc.
// Specialization constants select the variant: no dynamic branching on tile size, culling or AABB.
#extension GL_GOOGLE_include_directive : require
#include "culling.glsl.inc"

layout(constant_id = 0) const uint TILE = 16;
layout(constant_id = 1) const uint CULLING = 1;  // 0: every tile gets every light
layout(constant_id = 2) const uint AABB = 0;     // 1: Turanzkij's AABB test on top of the planes
layout(constant_id = 3) const uint SLICES = 0;   // 2..32: the 2.5D slab test (cull_ref.h); 0 off
// kList*: tile writes the capped index list, bitmask and zbin the tile's mask words (zbin: over the
// depth-sorted lights of SortedLights).
layout(constant_id = 4) const uint LIST_MODE = 0;
// 1: few lights (frame/passes/light_culling.h kInlineViewMaxLights): each tile puts them in view
// space itself, as before light_view.comp existed, which saves that pass and its barrier; the
// same toViewLight on the same operands, so the same decisions. Not with zbin (sorted lights).
layout(constant_id = 5) const uint INLINE_VIEW = 0;
layout(local_size_x_id = 0, local_size_y_id = 0) in;

uniform Frame { FrameConstants frame; };
readonly buffer Lights { GpuLight lights[]; };
readonly buffer Frustums { TileFrustum frustums[]; };
writeonly buffer Grid { LightGridEntry grid[]; };
writeonly buffer Indices { uint lightIndices[]; };
uniform sampler2D depthTex;
readonly buffer ViewLights { GpuViewLight viewLights[]; };  // light_view.comp.glsl
readonly buffer ViewSpheres { vec4 viewSpheres[]; };       // the same, spheres only
layout(push_constant) uniform Push { uint lightCount; } pc;

shared uint sMinDepthBits;  // positive floats order like their bit patterns
shared uint sMaxDepthBits;
shared uint sKept[kMaxLights / 32];
shared TileFrustum sFrustum;
shared float sZNear, sZFar;
shared vec3 sAabbMin, sAabbMax;
shared bool sEmpty;
shared float sSliceScale;
shared uint sDepthMask;
shared uint sTotal;


// bitmask, zbin: the tile's mask words written by every thread (no cap), the total counted.
void writeMask(uint tile, uint local, uint groupSize, uint lightCount, bool all) {
  const uint words = frame.lists.y;
  if (local == 0u) sTotal = 0u;
  barrier();
  for (uint w = local; w < words; w += groupSize) {
    uint bits = sKept[w];
    if (all) bits = w * 32u + 32u <= lightCount ? 0xFFFFFFFFu : (1u << (lightCount % 32u)) - 1u;
    lightIndices[tile * words + w] = bits;
    atomicAdd(sTotal, bitCount(bits));
  }
  barrier();
  if (local == 0u) grid[tile] = LightGridEntry(tile * words, sTotal, sTotal, 0);
}

void main() {
  const uint tile = gl_WorkGroupID.y * frame.tileCountX + gl_WorkGroupID.x;
  const uint local = gl_LocalInvocationIndex;
  const uint groupSize = TILE * TILE;
  const uint lightCount = min(pc.lightCount, kMaxLights);

  if (CULLING == 0 && LIST_MODE != kListTile) {
    writeMask(tile, local, groupSize, lightCount, true);
    return;
  }
  if (CULLING == 0) {
    // Culling off: every tile gets every light, in index order (thesis: "no optimisations").
    uint stored = min(lightCount, kMaxLightsPerTile);
    for (uint i = local; i < stored; i += groupSize) lightIndices[tile * kMaxLightsPerTile + i] = i;
    if (local == 0) grid[tile] = LightGridEntry(tile * kMaxLightsPerTile, stored, lightCount, 0);
    return;
  }

  if (local == 0) {
    sMinDepthBits = floatBitsToUint(1.0);
    sMaxDepthBits = 0u;
  }
  for (uint w = local; w < kMaxLights / 32; w += groupSize) sKept[w] = 0u;
  barrier();

  // Min/max depth over the tile's non-sky pixels (reverse-Z: the minimum is the farthest point).
  uvec2 px = gl_WorkGroupID.xy * TILE + gl_LocalInvocationID.xy;
  float d = 0.0;  // sky outside the image
  if (px.x < uint(frame.extent.x) && px.y < uint(frame.extent.y)) {
    d = texelFetch(depthTex, ivec2(px), 0).r;
    if (d > 0.0) {
      atomicMin(sMinDepthBits, floatBitsToUint(d));
      atomicMax(sMaxDepthBits, floatBitsToUint(d));
    }
  }
  barrier();

  if (local == 0) {
    float minDepth = uintBitsToFloat(sMinDepthBits), maxDepth = uintBitsToFloat(sMaxDepthBits);
    sEmpty = tileIsEmpty(maxDepth);  // an all-sky tile receives no light at all
    sZNear = viewZFromDepth(maxDepth, frame.proj[2][2], frame.proj[3][2]);
    sZFar = viewZFromDepth(minDepth, frame.proj[2][2], frame.proj[3][2]);
    sFrustum = frustums[tile];
    uvec2 extent = uvec2(frame.extent.xy);
    vec3 rays[4];
    tileCornerRays(tileRect(gl_WorkGroupID.xy, TILE, extent), extent, frame.proj[0][0], frame.proj[1][1], rays);
    vec3 lo, hi;
    tileAabb(rays, sZNear, sZFar, lo, hi);
    sAabbMin = lo;
    sAabbMax = hi;
    // applyDepthSlices in C++: a flat tile (zNear == zFar) is one slab.
    sSliceScale = sZNear > sZFar ? float(SLICES) / (sZNear - sZFar) : 0.0;
    sDepthMask = 0u;
  }
  barrier();

  if (SLICES > 0u) {
    if (d > 0.0) atomicOr(sDepthMask, 1u << sliceOf(sZNear, sSliceScale, SLICES, viewZFromDepth(d, frame.proj[2][2], frame.proj[3][2])));
    barrier();
  }

  // Each thread tests lights round-robin; the visible set is a bitmask so the stored list can be
  // written in ascending index order (the first kMaxLightsPerTile of them, as cull_ref.h does).
  // The range sphere's part of the test first, from 16 bytes a light (directional: an infinite
  // radius, which no plane or box rejects); the full test, which repeats it with the same operands
  // and so agrees, loads the rest only for the lights the sphere keeps.
  if (!sEmpty) {
    vec4 planes[6];
    for (int p = 0; p < 4; ++p) planes[p] = sFrustum.planes[p];
    planes[4] = nearPlane(sZNear);
    planes[5] = farPlane(sZFar);
    for (uint i = local; i < lightCount; i += groupSize) {
      // Few lights (INLINE_VIEW): the full test alone, on the light put in view space here, as
      // before the sphere-first test (which repeats part of the full one, a cost only many lights
      // repay). Many: the range sphere first, the rest of the light only where it passes.
      // Two separate bodies, so that many lights run the code they ran at 4b3dc94 (one body with
      // a GpuViewLight chosen by branch cost 3-7 % of light culling at 4K, 1000-4096 lights, H200).
      if (INLINE_VIEW == 1) {
        if (lightTouchesTile(toViewLight(lights[i], frame.view), sFrustum, sZNear, sZFar, sAabbMin, sAabbMax, AABB == 1,
                             SLICES, sSliceScale, sDepthMask))
          atomicOr(sKept[i / 32], 1u << (i % 32));
      } else {
        const vec4 sphere = viewSpheres[i];
        bool keep = true;
        for (int p = 0; p < 6; ++p) keep = keep && !sphereOutsidePlane(planes[p], sphere.xyz, sphere.w);
        if (AABB == 1) keep = keep && sphereOverlapsAabb(sAabbMin, sAabbMax, sphere.xyz, sphere.w);
        if (keep && lightTouchesTile(viewLights[i], sFrustum, sZNear, sZFar, sAabbMin, sAabbMax, AABB == 1, SLICES,
                                     sSliceScale, sDepthMask))
          atomicOr(sKept[i / 32], 1u << (i % 32));
      }
    }
  }
  barrier();

  if (LIST_MODE != kListTile) {
    writeMask(tile, local, groupSize, lightCount, false);
    return;
  }
  if (local == 0) {
    uint total = 0, stored = 0;
    for (uint w = 0; w < (lightCount + 31) / 32; ++w) {
      uint bits = sKept[w];
      total += bitCount(bits);
      while (bits != 0u && stored < kMaxLightsPerTile) {
        int b = findLSB(bits);
        bits &= bits - 1u;
        lightIndices[tile * kMaxLightsPerTile + stored++] = w * 32 + uint(b);
      }
    }
    grid[tile] = LightGridEntry(tile * kMaxLightsPerTile, stored, total, 0);
  }
}
