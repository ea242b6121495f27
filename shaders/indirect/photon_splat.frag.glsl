#version 460
// Photon splatting (splat=raster), fragment stage: at the pixel's own surface point y
// (surface.glsl.inc, as every pass of the frame takes it), the photon's irradiance
// (photon_splat.glsl.inc). Additive blending sums the photons (Eq. 5's sum) into the RGBA32F
// irradiance target, in slot order.
#extension GL_GOOGLE_include_directive : require
#include "surface_constants.glsl.inc"

#include "surface.glsl.inc"

#include "depth_texel.glsl.inc"
readonly buffer Photons { Photon photons[]; };
layout(location = 0) flat in uint inPhoton;
layout(location = 0) out vec4 outIrradiance;
#include "photon_splat.glsl.inc"

float depthAt(ivec2 p) { return fetchDepth(p); }

void main() {
  const ivec2 p = ivec2(gl_FragCoord.xy);
  if (!hasDepth(p)) discard;
  const vec3 y = worldPos(p);
  const vec3 ny = NORMALS == kNormalsGeometric ? geometricNormal(p, y) : reconstructNormal(p, y);
  SplatSetup sp;
  vec3 e;
  if (!splatSetup(photons[inPhoton], sp) || !splatAt(sp, y, ny, e)) discard;
  outIrradiance = vec4(e, 0.0);
}
