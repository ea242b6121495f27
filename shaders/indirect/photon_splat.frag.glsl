#version 460
// Photon splatting, fragment stage (the paper's Eq. 4-7; photon_ref.h splatIrradiance): at the
// pixel's own surface point y (surface.glsl.inc, as every pass of the frame takes it), the
// photon's irradiance E_p·π·K(|M_p(y − x_p)|) with E_p = Φ_p/A_p, A_p = (π/4)|du × dv|,
// Silverman's K(l) = (3/π)(1 − l²)², M_p's rows [dv × n; n × du; a·n]·2/(du·(dv × n)) and
// a = √|du·(dv × n)|. Only surfaces facing the way the photon's landing surface faces receive it.
// Additive blending sums the photons (Eq. 5's sum) into the RGBA32F irradiance target.
#extension GL_GOOGLE_include_directive : require
#include "surface_constants.glsl.inc"

#include "surface.glsl.inc"

#include "depth_texel.glsl.inc"
layout(set = 0, binding = HB_INDIRECT_PHOTONS) readonly buffer Photons { Photon photons[]; };
layout(location = 0) flat in uint inPhoton;
layout(location = 0) out vec4 outIrradiance;

float depthAt(ivec2 p) { return fetchDepth(p); }

void main() {
  const ivec2 p = ivec2(gl_FragCoord.xy);
  if (!hasDepth(p)) discard;
  const vec3 y = worldPos(p);
  const vec3 ny = NORMALS == kNormalsGeometric ? geometricNormal(p, y) : reconstructNormal(p, y);
  const Photon ph = photons[inPhoton];
  const vec3 x = ph.positionFluxR.xyz, du = ph.duFluxG.xyz, dv = ph.dvFluxB.xyz, n = ph.normalStatus.xyz;
  if (!(dot(ny, n) > 0.0)) discard;
  const vec3 dvn = cross(dv, n), ndu = cross(n, du);
  const float det = dot(du, dvn);
  const float area = length(cross(du, dv));
  if (!(abs(det) > 0.0) || !(area > 0.0)) discard;
  const vec3 r = y - x;
  const vec3 m = (2.0 / det) * vec3(dot(dvn, r), dot(ndu, r), sqrt(abs(det)) * dot(n, r));
  const float l2 = dot(m, m);
  if (!(l2 < 1.0)) discard;
  // E_p·π·K = Φ/((π/4)·area) · π · (3/π)(1 − l²)² = (12/π)·Φ·(1 − l²)²/area.
  const float w = 12.0 / 3.14159265358979 * (1.0 - l2) * (1.0 - l2) / area;
  outIrradiance = vec4(vec3(ph.positionFluxR.w, ph.duFluxG.w, ph.dvFluxB.w) * w, 0.0);
}
