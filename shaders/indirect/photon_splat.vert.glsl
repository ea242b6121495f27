#version 460
// Photon splatting (Aalund et al. 2015 Sect. 4.2, Frisvad et al. 2014), vertex stage: photon
// k = gl_VertexIndex / 6 becomes the quad x2 ± du/2 ± dv/2 (two triangles), the parallelogram
// its footprint ellipse is inscribed in (photon_ref.h splatIrradiance: l < 1 exactly inside it).
// The paper expands points in a geometry shader; six vertices a photon do the same without one.
// A slot that holds no stored photon becomes a degenerate triangle (nothing rasterized), so the
// draw is one fixed-order call over every slot: additive blending in primitive order makes the
// sum deterministic.
#extension GL_GOOGLE_include_directive : require
#include "shared/gpu_types.h"

uniform Frame { FrameConstants frame; };
readonly buffer Photons { Photon photons[]; };
layout(location = 0) flat out uint outPhoton;

const vec2 kCorners[6] = vec2[](vec2(-0.5, -0.5), vec2(0.5, -0.5), vec2(0.5, 0.5), vec2(-0.5, -0.5), vec2(0.5, 0.5),
                                vec2(-0.5, 0.5));

void main() {
  const uint k = uint(gl_VertexIndex) / 6u;
  outPhoton = k;
  const Photon p = photons[k];
  if (floatBitsToUint(p.normalStatus.w) != kPhotonStored) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // all six the same: no area
    return;
  }
  const vec2 c = kCorners[uint(gl_VertexIndex) % 6u];
  gl_Position = frame.viewProj * vec4(p.positionFluxR.xyz + c.x * p.duFluxG.xyz + c.y * p.dvFluxB.xyz, 1.0);
}
