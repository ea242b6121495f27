#version 460
// Shading from the visibility buffer (3D rasterization's per-pixel triangle id and view depth), in
// compute: no second rasterization of the scene. Per pixel: the triangle's three vertices, the
// barycentrics of the pixel-centre ray's hit (perspective-correct, as a rasterizer interpolates),
// the interpolated normal and uv, texture derivatives from the barycentrics of the neighbouring
// pixels' rays on the same plane (the paper's suggestion, Sect. 4), then the same direct light as
// the forward pass (shading_brdf.glsl.inc). Writes the same colour target; the analysis variant
// also the triangle's true face normal.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_nonuniform_qualifier : require
#include "shared/gpu_types.h"

layout(constant_id = 0) const uint TILE = 16;
layout(constant_id = 1) const uint USE_GRID = 1;
layout(constant_id = 2) const uint SHADOWS = 1;
layout(constant_id = 3) const uint ANALYSIS = 0;
layout(constant_id = 4) const uint INDIRECT = 0;  // 1: add the indirect light (HB_SHADE_VB_INDIRECT)
layout(local_size_x = 8, local_size_y = 8) in;

layout(constant_id = 5) const uint LIST_MODE = 0;  // kList*: the light lists
layout(constant_id = 6) const uint AMBIENT = 0;     // 1: ambient occlusion runs (the ambient term)
layout(constant_id = 7) const uint ONE_WORD = 1;    // 1: at most 32 lights a pixel, one visibility word

#include "shading_bindings.glsl.inc"
layout(set = 0, binding = HB_SHADE_VB_VISIBILITY_IDS) readonly buffer VisibilityIds { uint visWords[]; };  // (id, t bits) per pixel
layout(set = 0, binding = HB_SHADE_VB_RAYS) uniform Rays { Raster3dConstants rays; };
layout(set = 0, binding = HB_SHADE_VB_DRAWS) readonly buffer Draws { GpuDraw draws[]; };
layout(set = 0, binding = HB_SHADE_VB_TRIANGLE_DRAWS) readonly buffer TriangleDraws { uint triangleDraw[]; };
layout(set = 0, binding = HB_SHADE_VB_COLOR, rgba16f) uniform writeonly image2D colorImage;
layout(set = 0, binding = HB_SHADE_VB_REF_NORMAL, rgba32f) uniform writeonly image2D refNormalImage;
layout(set = 0, binding = HB_SHADE_VB_AO) readonly buffer AmbientOcclusion { float aoValues[]; };  // frame.ambient.w = 1 only
layout(set = 0, binding = HB_SHADE_VB_INDIRECT, rgba32f) uniform readonly image2D indirectImage;  // INDIRECT = 1 only
layout(set = 0, binding = HB_SHADE_VB_TEXTURES) uniform sampler2D textures[];  // bindless: the last binding

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

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= int(frame.extent.x) || p.y >= int(frame.extent.y)) return;
  const uint id = visWords[2u * (uint(p.y) * uint(frame.extent.x) + uint(p.x))];
  if (id == 0xFFFFFFFFu) {  // sky: opaque black, no normal (the forward pass's clear values)
    imageStore(colorImage, p, vec4(0.0, 0.0, 0.0, 1.0));
    if (ANALYSIS == 1) imageStore(refNormalImage, p, vec4(0.0));
    return;
  }
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
  imageStore(colorImage, p, vec4(shadeDirectView(p, worldPos, v, n, base.rgb, metallic, roughness), 1.0));
  if (ANALYSIS == 1) {
    const float len2 = dot(face, face);
    vec3 fn = len2 > 0.0 ? face / sqrt(len2) : vec3(0.0);
    if (dot(fn, v) < 0.0) fn = -fn;
    imageStore(refNormalImage, p, vec4(fn, len2 > 0.0 ? 1.0 : 0.0));
  }
}
