#version 460
// Pass 3 (thesis 4.2.3): tiled light culling, gather approach, one workgroup per tile. Mirrors
// cull_ref.h (tileDepthRange, tileVolume, lightPassesPlanes, lightPassesAabb, cullTile) op for op.
// Specialization constants select the variant: no dynamic branching on tile size, culling or AABB.
#extension GL_GOOGLE_include_directive : require
#include "shared/gpu_types.h"

layout(constant_id = 0) const uint TILE = 16;
layout(constant_id = 1) const uint CULLING = 1;  // 0: every tile gets every light
layout(constant_id = 2) const uint AABB = 0;     // 1: Turanzkij's AABB test on top of the planes
layout(local_size_x_id = 0, local_size_y_id = 0) in;

const uint kMaxLights = 4096;  // the visible-set bitmask below; the host refuses more

layout(set = 0, binding = 0) uniform Frame { FrameConstants frame; };
layout(set = 0, binding = 1) readonly buffer Lights { GpuLight lights[]; };
layout(set = 0, binding = 2) readonly buffer Frustums { TileFrustum frustums[]; };
layout(set = 0, binding = 3) writeonly buffer Grid { LightGridEntry grid[]; };
layout(set = 0, binding = 4) writeonly buffer Indices { uint lightIndices[]; };
layout(set = 0, binding = 5) uniform sampler2D depthTex;
layout(push_constant) uniform Push { uint lightCount; } pc;

shared uint sMinDepthBits;  // positive floats order like their bit patterns
shared uint sMaxDepthBits;
shared uint sKept[kMaxLights / 32];
shared vec4 sPlanes[6];
shared vec3 sAabbMin, sAabbMax;
shared bool sEmpty;

float viewZFromDepth(float depth) { return -frame.proj[3][2] / (depth + frame.proj[2][2]); }

bool sphereOutsidePlane(vec4 plane, vec3 c, float r) { return dot(plane.xyz, c) + plane.w < -r; }

bool coneOutsidePlane(vec4 plane, vec3 tip, vec3 axis, float h, float baseRadius) {
  if (!(dot(plane.xyz, tip) + plane.w < 0.0)) return false;
  // cross(cross(a, n), a) = n - (a.n) a for unit a: the unit direction in the base plane farthest
  // along n; zero when n is parallel to the axis (then every base point is equally far).
  vec3 v = cross(cross(axis, plane.xyz), axis);
  float len2 = dot(v, v);
  vec3 q = tip + axis * h;
  if (len2 > 0.0) q += v * (baseRadius / sqrt(len2));
  return dot(plane.xyz, q) + plane.w < 0.0;
}

bool lightTouchesTile(GpuLight l) {
  if (l.type == kLightDirectional) return true;
  vec3 c = vec3(frame.view * vec4(l.positionRange.xyz, 1.0));
  float r = l.positionRange.w;
  for (int i = 0; i < 6; ++i)
    if (sphereOutsidePlane(sPlanes[i], c, r)) return false;
  if (l.type == kLightSpot && l.tanOuter >= 0.0) {
    vec3 axis = normalize(mat3(frame.view) * l.directionCosOuter.xyz);
    float baseRadius = r * l.tanOuter;
    for (int i = 0; i < 6; ++i)
      if (coneOutsidePlane(sPlanes[i], c, axis, r, baseRadius)) return false;
  }
  if (AABB == 1) {
    float d2 = 0.0;
    for (int i = 0; i < 3; ++i) {
      if (c[i] < sAabbMin[i]) d2 += (sAabbMin[i] - c[i]) * (sAabbMin[i] - c[i]);
      else if (c[i] > sAabbMax[i]) d2 += (c[i] - sAabbMax[i]) * (c[i] - sAabbMax[i]);
    }
    if (!(d2 <= r * r)) return false;
  }
  return true;
}

vec3 cornerRay(uvec2 px) {
  vec2 ndc = 2.0 * (vec2(px) / frame.extent.xy) - 1.0;
  return vec3(ndc.x / frame.proj[0][0], ndc.y / frame.proj[1][1], -1.0);
}

void main() {
  const uint tile = gl_WorkGroupID.y * frame.tileCountX + gl_WorkGroupID.x;
  const uint local = gl_LocalInvocationIndex;
  const uint groupSize = TILE * TILE;
  const uint lightCount = min(pc.lightCount, kMaxLights);

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
  if (px.x < uint(frame.extent.x) && px.y < uint(frame.extent.y)) {
    float d = texelFetch(depthTex, ivec2(px), 0).r;
    if (d > 0.0) {
      atomicMin(sMinDepthBits, floatBitsToUint(d));
      atomicMax(sMaxDepthBits, floatBitsToUint(d));
    }
  }
  barrier();

  if (local == 0) {
    float minDepth = uintBitsToFloat(sMinDepthBits), maxDepth = uintBitsToFloat(sMaxDepthBits);
    sEmpty = !(maxDepth > 0.0);  // an all-sky tile receives no light at all
    float zNear = viewZFromDepth(maxDepth), zFar = viewZFromDepth(minDepth);
    for (int i = 0; i < 4; ++i) sPlanes[i] = frustums[tile].planes[i];
    sPlanes[4] = vec4(0.0, 0.0, -1.0, zNear);
    sPlanes[5] = vec4(0.0, 0.0, 1.0, -zFar);
    uvec2 size = uvec2(frame.extent.xy);
    uvec2 p0 = gl_WorkGroupID.xy * TILE;
    uvec2 p1 = min(p0 + TILE, size);
    vec3 rays[4] = vec3[4](cornerRay(uvec2(p0.x, p0.y)), cornerRay(uvec2(p1.x, p0.y)), cornerRay(uvec2(p1.x, p1.y)),
                           cornerRay(uvec2(p0.x, p1.y)));
    vec3 lo = vec3(1e30), hi = vec3(-1e30);
    for (int i = 0; i < 4; ++i) {
      vec3 a = rays[i] * -zNear, b = rays[i] * -zFar;
      lo = min(lo, min(a, b));
      hi = max(hi, max(a, b));
    }
    sAabbMin = lo;
    sAabbMax = hi;
  }
  barrier();

  // Each thread tests lights round-robin; the visible set is a bitmask so the stored list can be
  // written in ascending index order (the first kMaxLightsPerTile of them, as cull_ref.h does).
  if (!sEmpty)
    for (uint i = local; i < lightCount; i += groupSize)
      if (lightTouchesTile(lights[i])) atomicOr(sKept[i / 32], 1u << (i % 32));
  barrier();

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
