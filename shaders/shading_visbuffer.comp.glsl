#version 460
// Shading from the visibility buffer (3D rasterization's per-pixel triangle id and view depth), in
// compute: no second rasterization of the scene. Per pixel: the triangle's three vertices, the
// barycentrics of the pixel-centre ray's hit (perspective-correct, as a rasterizer interpolates),
// the interpolated normal and uv, texture derivatives from the barycentrics of the neighbouring
// pixels' rays on the same plane (the paper's suggestion, Sect. 4), then the same direct light as
// the forward pass (shading_brdf.glsl.inc). Writes the same colour target; the analysis variant
// also the triangle's true face normal.
// Anti-aliasing (AA_STORED > 0, docs/methods/3d-rasterization.md "Anti-aliasing"): the visibility
// buffer holds after the pixel-centre plane one plane per stored sample; each distinct triangle
// among the pixel's samples is shaded once, at the pixel-centre ray's point on its plane (as a
// multisampling rasterizer shades at the pixel centre), with the pixel's shadow and effect terms
// (shading_terms.glsl.inc), and weighted by its share of the samples (the resolve). CSAA: the 12 coverage samples go
// to the nearest of the stored samples' triangles that covers them, or are dropped.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_nonuniform_qualifier : require
#include "shared/gpu_types.h"

layout(constant_id = 0) const uint TILE = 16;
layout(constant_id = 1) const uint USE_GRID = 1;
layout(constant_id = 2) const uint SHADOWS = 1;
layout(constant_id = 3) const uint ANALYSIS = 0;
layout(local_size_x = 8, local_size_y = 8) in;

layout(constant_id = 4) const uint LIST_MODE = 0;  // kList*: the light lists
layout(constant_id = 5) const uint ONE_WORD = 1;    // 1: at most 32 lights a pixel, one visibility word
layout(constant_id = 6) const uint AA_STORED = 0;    // anti-aliasing: stored samples (planes after the centre's)
layout(constant_id = 7) const uint CSAA = 0;         // 1: csaa-4-12 (AA_STORED = 4)
layout(constant_id = 8) const uint PLANE_STRIDE = 0;  // entries from one plane to the next
// 16 and after: the effects' terms (shading_terms.glsl.inc).

#include "shading_bindings.glsl.inc"
readonly buffer VisibilityIds { uint visWords[]; };  // (id, t bits) per pixel
uniform Rays { Raster3dConstants rays; };
readonly buffer Draws { GpuDraw draws[]; };
readonly buffer TriangleDraws { uint triangleDraw[]; };
layout(rgba16f) uniform writeonly image2D colorImage;
layout(rgba32f) uniform writeonly image2D refNormalImage;
uniform sampler2D textures[];  // bindless: the last binding

#include "shading_brdf.glsl.inc"
#include "camera_ray.glsl.inc"

struct Corner {
  vec3 position, normal;
  vec2 uv;
};

Corner corner(GpuDraw draw, uint index) {
  const uint v = (draw.vertexOffset + index) * 8u;
  Corner c;
  c.position = vec3(vertexData[v], vertexData[v + 1u], vertexData[v + 2u]);
  c.normal = vec3(vertexData[v + 3u], vertexData[v + 4u], vertexData[v + 5u]);
  c.uv = vec2(vertexData[v + 6u], vertexData[v + 7u]);
  return c;
}

// Barycentrics (of vertices 1 and 2) of the ray org + s·dir with the triangle's plane; the
// extrapolated values for a ray off the triangle (the neighbours' rays for derivatives).
vec2 barycentrics(vec3 a, vec3 b, vec3 c, vec3 org, vec3 dir) {
  const vec3 e1 = b - a, e2 = c - a, pv = cross(dir, e2);
  const float det = dot(e1, pv);
  const vec3 tv = org - a;
  const float inv = 1.0 / det;
  return vec2(dot(tv, pv) * inv, dot(dir, cross(tv, e1)) * inv);
}

vec4 sampleTexture(int index, vec2 uv, vec2 uvDx, vec2 uvDy) {
  return textureGrad(textures[nonuniformEXT(index)], uv, uvDx, uvDy);
}

struct Shaded {
  vec3 color, faceNormal;  // faceNormal: towards the viewer, 0 for a degenerate triangle
  float faceValid;
};

// The world-space corners of triangle `id`, as the forward vertex shader computes them.
void worldCorners(uint id, out vec3 w0, out vec3 w1, out vec3 w2) {
  const GpuDraw draw = draws[triangleDraw[id]];
  const uint first = draw.firstIndex + 3u * (id - draw.triangleBase);
  w0 = (draw.model * vec4(corner(draw, sceneIndices[first]).position, 1.0)).xyz;
  w1 = (draw.model * vec4(corner(draw, sceneIndices[first + 1u]).position, 1.0)).xyz;
  w2 = (draw.model * vec4(corner(draw, sceneIndices[first + 2u]).position, 1.0)).xyz;
}

Shaded shadeTriangle(ivec2 p, uint id) {
  const GpuDraw draw = draws[triangleDraw[id]];
  const uint first = draw.firstIndex + 3u * (id - draw.triangleBase);
  const Corner c0 = corner(draw, sceneIndices[first]), c1 = corner(draw, sceneIndices[first + 1u]),
               c2 = corner(draw, sceneIndices[first + 2u]);
  // World positions as the forward vertex shader computes them.
  const vec3 w0 = (draw.model * vec4(c0.position, 1.0)).xyz, w1 = (draw.model * vec4(c1.position, 1.0)).xyz,
             w2 = (draw.model * vec4(c2.position, 1.0)).xyz;
  // The pixel's ray and its right and lower neighbours' (camera_ray.glsl.inc; for a perspective
  // view exactly d + rayDx and d + rayDy up to rounding).
  const uint proj = rays.projection;
  const float x = float(p.x), y = float(p.y);
  const vec3 org = cameraRayOrigin(proj, rays, x, y), d = cameraRayDir(proj, rays, x, y);
  const vec2 b = barycentrics(w0, w1, w2, org, d);
  const vec2 bx = barycentrics(w0, w1, w2, cameraRayOrigin(proj, rays, x + 1.0, y), cameraRayDir(proj, rays, x + 1.0, y));
  const vec2 by = barycentrics(w0, w1, w2, cameraRayOrigin(proj, rays, x, y + 1.0), cameraRayDir(proj, rays, x, y + 1.0));
  const vec3 lambda = vec3(1.0 - b.x - b.y, b.x, b.y);
  const vec2 uv = lambda.x * c0.uv + lambda.y * c1.uv + lambda.z * c2.uv;
  const vec2 uvX = (1.0 - bx.x - bx.y) * c0.uv + bx.x * c1.uv + bx.y * c2.uv;
  const vec2 uvY = (1.0 - by.x - by.y) * c0.uv + by.x * c1.uv + by.y * c2.uv;
  const vec2 uvDx = uvX - uv, uvDy = uvY - uv;
  const vec3 worldPos = lambda.x * w0 + lambda.y * w1 + lambda.z * w2;

  const GpuMaterial m = materials[draw.material];
  vec4 base = m.baseColorFactor;
  if (m.baseColorTexture >= 0) base *= sampleTexture(m.baseColorTexture, uv, uvDx, uvDy);
  float metallic = m.metallicFactor, roughness = m.roughnessFactor;
  if (m.metallicRoughnessTexture >= 0) {
    const vec4 mr = sampleTexture(m.metallicRoughnessTexture, uv, uvDx, uvDy);
    roughness *= mr.g;
    metallic *= mr.b;
  }
  roughness = clamp(roughness, 0.04, 1.0);
  metallic = clamp(metallic, 0.0, 1.0);
  vec3 n = normalize(mat3(draw.normalMatrix) * (lambda.x * c0.normal + lambda.y * c1.normal + lambda.z * c2.normal));
  // Double-sided: shade the side the eye sees (the forward pass's gl_FrontFacing): the side of
  // the triangle's plane the eye is on, against its winding's normal.
  const vec3 face = cross(w1 - w0, w2 - w0);
  if (dot(face, org - w0) < 0.0) n = -n;
  // The viewer: the eye of a perspective view (as the forward pass), else back along the ray.
  const vec3 v = proj == kProjectionPerspective ? normalize(frame.cameraPos.xyz - worldPos) : -normalize(d);
  Shaded r;
  r.color = shadeDirectView(p, worldPos, v, n, base.rgb, metallic, roughness);
  r.faceNormal = vec3(0.0);
  r.faceValid = 0.0;
  if (ANALYSIS == 1) {
    const float len2 = dot(face, face);
    vec3 fn = len2 > 0.0 ? face / sqrt(len2) : vec3(0.0);
    if (dot(fn, v) < 0.0) fn = -fn;
    r.faceNormal = fn;
    r.faceValid = len2 > 0.0 ? 1.0 : 0.0;
  }
  return r;
}

// CSAA's coverage samples: the 16x standard pattern's last 12 (aa_samples.h kCsaaCoverage).
const vec2 kCsaaCoverage[12] = vec2[](vec2(0.1875, 0.375), vec2(0.625, 0.8125), vec2(0.8125, 0.6875),
                                      vec2(0.6875, 0.1875), vec2(0.375, 0.875), vec2(0.5, 0.0625), vec2(0.25, 0.125),
                                      vec2(0.125, 0.75), vec2(0.0, 0.5), vec2(0.9375, 0.25), vec2(0.875, 0.9375),
                                      vec2(0.0625, 0.0));

// The resolve: each distinct triangle of the pixel's samples shaded once, weighted by its samples.
vec3 resolveSamples(ivec2 p, uint pixel) {
  const uint kMax = 16u;  // aa_samples.h: at most 16 stored samples
  uint ids[16];
  float weight[16];
  uint n = 0u;
  float total = 0.0;
  for (uint s = 0u; s < AA_STORED; ++s) {
    const uint id = visWords[2u * ((s + 1u) * PLANE_STRIDE + pixel)];
    uint k = 0u;
    while (k < n && ids[k] != id) ++k;
    if (k == n) {
      ids[n] = id;
      weight[n] = 0.0;
      ++n;
    }
    weight[k] += 1.0;
    total += 1.0;
  }
  if (CSAA == 1u) {
    // Each coverage sample's ray against the stored triangles (at most 4, their corners fetched
    // once); the nearest hit takes it.
    vec3 c0[4], c1[4], c2[4];
    for (uint k = 0u; k < n; ++k)
      if (ids[k] != 0xFFFFFFFFu) worldCorners(ids[k], c0[k], c1[k], c2[k]);
    const uint proj = rays.projection;
    for (uint s = 0u; s < 12u; ++s) {
      const float sx = float(p.x) + kCsaaCoverage[s].x - 0.5, sy = float(p.y) + kCsaaCoverage[s].y - 0.5;
      const vec3 org = cameraRayOrigin(proj, rays, sx, sy), dir = cameraRayDir(proj, rays, sx, sy);
      float best = 1.0 / 0.0;
      uint bestK = kMax;
      for (uint k = 0u; k < n; ++k) {
        if (ids[k] == 0xFFFFFFFFu) continue;
        const vec3 w0 = c0[k], w1 = c1[k], w2 = c2[k];
        const vec2 b = barycentrics(w0, w1, w2, org, dir);
        if (!(b.x >= 0.0 && b.y >= 0.0 && b.x + b.y <= 1.0)) continue;
        const vec3 hit = (1.0 - b.x - b.y) * w0 + b.x * w1 + b.y * w2;
        const float t = dot(hit - org, dir);
        if (t > 0.0 && t < best) best = t, bestK = k;
      }
      if (bestK == kMax) {  // no stored triangle covers it: the sky if a stored sample saw it, else dropped
        for (uint k = 0u; k < n; ++k)
          if (ids[k] == 0xFFFFFFFFu) bestK = k;
      }
      if (bestK < kMax) {
        weight[bestK] += 1.0;
        total += 1.0;
      }
    }
  }
  vec3 sum = vec3(0.0);
  for (uint k = 0u; k < n; ++k)
    if (ids[k] != 0xFFFFFFFFu) sum += weight[k] * shadeTriangle(p, ids[k]).color;  // the sky is black
  return sum / total;
}

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= int(frame.extent.x) || p.y >= int(frame.extent.y)) return;
  const uint pixel = uint(p.y) * uint(frame.extent.x) + uint(p.x);
  const uint id = visWords[2u * pixel];
  if (AA_STORED > 0u) {
    imageStore(colorImage, p, vec4(resolveSamples(p, pixel), 1.0));
    if (ANALYSIS == 1) {  // the centre's triangle, as without anti-aliasing
      const Shaded c = id == 0xFFFFFFFFu ? Shaded(vec3(0.0), vec3(0.0), 0.0) : shadeTriangle(p, id);
      imageStore(refNormalImage, p, vec4(c.faceNormal, c.faceValid));
    }
    return;
  }
  if (id == 0xFFFFFFFFu) {  // sky: opaque black, no normal (the forward pass's clear values)
    imageStore(colorImage, p, vec4(0.0, 0.0, 0.0, 1.0));
    if (ANALYSIS == 1) imageStore(refNormalImage, p, vec4(0.0));
    return;
  }
  const Shaded c = shadeTriangle(p, id);
  imageStore(colorImage, p, vec4(c.color, 1.0));
  if (ANALYSIS == 1) imageStore(refNormalImage, p, vec4(c.faceNormal, c.faceValid));
}
