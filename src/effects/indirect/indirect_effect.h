// Single-bounce indirect light (Aalund, Frisvad, Bærentzen 2015, Sect. 3.4 and 4.2): light from
// each point or spot light that reaches a surface, is reflected diffusely once and lands where the
// camera sees it (LDDE paths). Primary photons leave each light through the texels of image planes
// (6 cube faces for a point light, one face over a spot light's cone), each split at its first hit
// into the N LDM directions, each split photon traced to where it lands and splatted there with
// its photon differential (Silverman's kernel through the filter matrix M_p).
// Value: false | true (the defaults below) | an object of these settings, each optional:
//   method          "ldm" (the split photons traced through layered depth maps, the paper's)
//                   | "raytraced" (the same photons traced by the ray tracer: differs from ldm by
//                     the LDM approximation alone)
//                   | "reference" (gathered: per pixel `samples` cosine-weighted rays to the
//                     surfaces they meet, lit directly (with shadow rays) and reflecting
//                     diffusely: the converged single bounce)
//   directions      N, the split directions (each used the way into the surface's hemisphere)
//                   1..2048                                                   default 64
//   ldm_resolution  R of each map, 8..4096                                    default 128
//   photons         primary photons per face side (a point light emits 6·photons², a spot
//                   light photons²), 1..1024                                  default 16
//   bias            scale of the derived LDM bias (ldm_trace.glsl.inc), > 0   default 1
//   ldm_list, ldm_build   as effects.ambient_occlusion's
//   samples         reference rays per pixel, a square 16..65536              default 256
//   footprint       "rotated" (the paper's: the incoming directional differentials rotated onto
//                   the split direction) | "cell" (spanning the split direction's share of the
//                   sphere, 2π/N: indirect_common.glsl.inc splitDifferentials)      default rotated
//   bounces         K, the diffuse bounces (Sect. 6 "Multiple Bounces"), 1..4   default 1
//   bounce_directions  M: a photon landing after bounce b >= 1 splits again into
//                   M_{b+1} = max(1, M >> (b − 1)) of the N directions (halving per bounce), an
//                   evenly strided subset turned by a hash of its slot, 1..2048   default 8
// It acts when the scene has a point or spot light (directional lights emit no photons here: the
// paper's method is for point lights); the frame then composes direct + ambient·AO + indirect,
// the indirect light reflected as Lambertian: albedo·(1 − metallic)/π · E_indirect.
#pragma once
#include <cstdint>
#include <string>

#include "plan/effect.h"
#include "plan/ldm_settings.h"

namespace hb {

enum class IndirectMethod : uint32_t { Ldm = 0, RayTraced = 1, Reference = 2 };
const char* toString(IndirectMethod m);
// How the photons reach the pixels: a compute pass that bins them into tiles and gathers them in
// slot order (the default), or a quad a photon through the raster pipeline's additive blending.
enum class IndirectSplat : uint32_t { Compute = 0, Raster = 1 };
const char* toString(IndirectSplat s);

struct IndirectSettings {
  IndirectMethod method = IndirectMethod::Ldm;
  uint32_t directions = 64;
  uint32_t ldmResolution = 128;
  uint32_t photons = 16;
  double bias = 1.0;
  LdmList ldmList = LdmList::Max64;
  LdmBuildMethod ldmBuild = LdmBuildMethod::Hardware;
  uint32_t samples = 256;
  IndirectSplat splat = IndirectSplat::Compute;
  uint32_t splatBin = 128;     // splat=compute: a coarse bin's side in pixels
  double maxAnisotropy = 0;    // a footprint's axis ratio at most this, its short axis widened (0: off)
  bool cellFootprint = false;  // footprint "cell" (else "rotated", the paper's)
  uint32_t bounces = 1;
  uint32_t bounceDirections = 8;
  // splat=compute, bounces > 1: bounces 2..K splatted at one receiver in f x f pixels and interpolated
  // on each pixel's own surface (1: at every pixel, the exact splat).
  uint32_t laterBounceStride = 1;
  // The directions a photon landing after bounce b - 1 splits into at bounce b (1-based): N at the
  // first, then min(N, max(1, M >> (b − 2))).
  uint32_t directionsAtBounce(uint32_t b) const {
    if (b <= 1) return directions;
    const uint32_t m = bounceDirections >> (b - 2);
    return m < 1 ? 1 : (m > directions ? directions : m);
  }
  nlohmann::json toJson() const;
};

// The settings of a value that passed validation (true: the defaults). Precondition: called for.
IndirectSettings indirectSettingsOf(const nlohmann::json& value);

const EffectDef& indirectEffect();
void reportIndirect(EffectReport& report);  // indirect_report.cpp

}  // namespace hb
