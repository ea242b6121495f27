#version 460
// Shading pass (thesis 4.4 / 2.7): Cook-Torrance — Lambert diffuse + specular with Schlick's
// Fresnel, the GGX/Trowbridge-Reitz distribution and Smith with Schlick-GGX geometry; k_s from
// Fresnel, k_d = (1 - k_s)(1 - metallic). glTF punctual lights (candela / lux), a distance
// attenuation that reaches zero at the range, spot cone falloff; visibility from the shadow
// pass's bitmask. No emission; the terms the frame's effects declare (shading_terms.glsl.inc) added. Writes linear HDR colour; the analysis variant also
// writes the true face normal of the triangle (the reference for normal reconstruction).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_nonuniform_qualifier : require
#include "shared/gpu_types.h"

layout(constant_id = 0) const uint TILE = 16;
layout(constant_id = 1) const uint USE_GRID = 1;  // 0: no culling pass ran, loop over all lights
layout(constant_id = 2) const uint SHADOWS = 1;   // 0: every light visible
layout(constant_id = 3) const uint ANALYSIS = 0;  // 1: also write the reference normal
// 1: primary visibility came from 3D rasterization (frame/passes/raster3d.h): the depth test
// is off and a fragment is shaded only where its triangle is the one the visibility buffer holds.
layout(constant_id = 4) const uint ID_MATCH = 0;
layout(constant_id = 5) const uint LIST_MODE = 0;  // kList*: the light lists
// What a frame does not use costs it nothing (frame/passes/shading.h ShadingInputs):
layout(constant_id = 6) const uint ONE_WORD = 1;     // 1: at most 32 lights a pixel, one visibility word
layout(constant_id = 7) const uint PERSPECTIVE = 1;  // 1: a perspective view, v = the eye minus the point
// 16 and after: the effects' terms (shading_terms.glsl.inc).

#include "shading_bindings.glsl.inc"
uniform sampler2D textures[];  // bindless: the last binding
readonly buffer VisibilityIds { uint visWords[]; };  // ID_MATCH: (id, t bits) per pixel
layout(push_constant) uniform Push { DrawConstants draw; };

#include "shading_brdf.glsl.inc"

// ... towards the viewer (camera_ray.glsl.inc; a perspective view without its orthographic branch).
vec3 shadeDirect(ivec2 p, vec3 worldPos, vec3 n, vec3 base, float metallic, float roughness) {
  const vec3 v = PERSPECTIVE == 1 ? normalize(frame.cameraPos.xyz - worldPos) : towardsViewer(frame, worldPos);
  return shadeDirectView(p, worldPos, v, n, base, metallic, roughness);
}

layout(location = 0) in vec3 inWorldPos;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUv;
layout(location = 0) out vec4 outColor;
layout(location = 1) out vec4 outRefNormal;

vec3 vertexPosition(uint index) {
  uint v = (draw.vertexOffset + index) * 8u;
  return vec3(vertexData[v], vertexData[v + 1], vertexData[v + 2]);
}

vec4 sampleTexture(int index, vec2 uvDx, vec2 uvDy) {
  // ID_MATCH: derivatives were taken before the discard, in uniform control flow.
  if (ID_MATCH == 1) return textureGrad(textures[nonuniformEXT(index)], inUv, uvDx, uvDy);
  return texture(textures[nonuniformEXT(index)], inUv);
}

void main() {
  vec2 uvDx = vec2(0.0), uvDy = vec2(0.0);
  if (ID_MATCH == 1) {
    uvDx = dFdx(inUv);
    uvDy = dFdy(inUv);
    const uint pixel = uint(gl_FragCoord.y) * uint(frame.extent.x) + uint(gl_FragCoord.x);
    if (visWords[2u * pixel] != draw.triangleBase + uint(gl_PrimitiveID)) discard;  // low word: the id
  }
  GpuMaterial m = materials[draw.material];
  vec4 base = m.baseColorFactor;
  if (m.baseColorTexture >= 0) base *= sampleTexture(m.baseColorTexture, uvDx, uvDy);
  float metallic = m.metallicFactor, roughness = m.roughnessFactor;
  if (m.metallicRoughnessTexture >= 0) {
    vec4 mr = sampleTexture(m.metallicRoughnessTexture, uvDx, uvDy);
    roughness *= mr.g;  // glTF: green = roughness, blue = metallic
    metallic *= mr.b;
  }
  roughness = clamp(roughness, 0.04, 1.0);
  metallic = clamp(metallic, 0.0, 1.0);

  vec3 n = normalize(inNormal);
  if (!gl_FrontFacing) n = -n;  // double-sided: shade the side we see
  vec3 color = shadeDirect(ivec2(gl_FragCoord.xy), inWorldPos, n, base.rgb, metallic, roughness);
  outColor = vec4(color, 1.0);

  if (ANALYSIS == 1) {
    // The triangle's true face normal from its three vertices (not the interpolated one).
    uint t = draw.firstIndex + uint(gl_PrimitiveID) * 3u;
    vec3 a = (draw.model * vec4(vertexPosition(sceneIndices[t]), 1.0)).xyz;
    vec3 b = (draw.model * vec4(vertexPosition(sceneIndices[t + 1u]), 1.0)).xyz;
    vec3 c = (draw.model * vec4(vertexPosition(sceneIndices[t + 2u]), 1.0)).xyz;
    vec3 fn = cross(b - a, c - a);
    float len2 = dot(fn, fn);
    fn = len2 > 0.0 ? fn / sqrt(len2) : vec3(0.0);
    if (dot(fn, towardsViewer(frame, inWorldPos)) < 0.0) fn = -fn;
    outRefNormal = vec4(fn, len2 > 0.0 ? 1.0 : 0.0);
  }
}
