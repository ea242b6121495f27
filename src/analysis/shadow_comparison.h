// The CPU shadow reference: the GPU shadow pass repeated in double and compared with its mask.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "frame/renderer.h"
#include "reference/bvh.h"
#include "scene/scene.h"

namespace hb {

// The GPU shadow pass repeated in double with `bvh`, from the GPU's own positions and normals
// (shaders/shadows/shadows_common.glsl.inc): per pixel, per light i of its tile list, the same at-light,
// range/cone (rangeTest), N·L and castShadows decisions, then Bvh::occluded(P, L, tMin, tMax)
// with tMin = gpu::shadowTMin(cameraPos, P) (cameraPos as in FrameConstants: w = 0 gives the
// thesis's constant kShadowTMin, w = kShadowTMinPerMetre the scaled one); then compared with the
// GPU's mask. A mismatching pair is EXPLAINED when float rounding may decide it either way, with δ = kFloatRayShift ·
// (|P| + min(tMax, scene diagonal)):
//  - nearTie: |N·L| or the range/cone margin is within 16 float ulps of its operands (the GPU
//    takes these decisions in float);
//  - endpoint: the CPU answer for [tMin − δ, tMax + δ] differs from [tMin + δ, tMax − δ] (a hit
//    at the ray's ends: t_min self-intersection or geometry at the light);
//  - grazing: the CPU answer changes when the origin moves by δ along ±x, ±y, ±z (the ray passes
//    within δ of a triangle's edge or silhouette).
// δ: lavapipe intersects in float; its edge functions are formed from vertex − origin
// differences and products with relative error a few eps (2^-24) of the magnitudes involved,
// which are bounded by |P| + t; the ray direction itself is normalised in float (another few eps,
// i.e. a displacement of a few eps · t at distance t). 2^-17 = 128 eps leaves a wide margin for
// the accumulated dozens of operations of the traversal and test, and still is 8 µm at 1 m.
inline constexpr double kFloatRayShift = 1.0 / 131072.0;  // 2^-17

struct ShadowComparison {
  std::vector<uint32_t> visibility;  // the CPU's words, laid out as ShadowReadback::visibility
  uint64_t pairs = 0;                // (pixel, light) pairs compared (non-sky × tile count)
  uint64_t rays = 0;                 // pairs where the CPU traced a ray
  uint64_t mismatches = 0;
  uint64_t nearTie = 0, endpoint = 0, grazing = 0;  // explained mismatches, by first reason found
  uint64_t unexplained() const { return mismatches - nearTie - endpoint - grazing; }
  void addCounts(const ShadowComparison& other);  // every count (not visibility)
};
// Preconditions as accountRays; shadows from an analysis frame.
ShadowComparison compareShadows(const Scene& scene, const Bvh& bvh, const ShadowReadback& shadows,
                                const CullingReadback& culling, uint32_t width, uint32_t height, uint32_t tileSize,
                                bool rangeTest, const glm::vec4& cameraPos = glm::vec4(0.0f));

}  // namespace hb
