// The true surface seen by each pixel of a frame: the eye ray intersected with the scene in double.
// Images are row-major, width × height, top row first; depth 0 = sky.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "reference/bvh.h"
#include "reference/reconstruct_ref.h"

namespace hb {

enum class SurfaceState : uint8_t {
  Sky,        // depth 0: nothing rasterised
  Matched,    // the eye ray hits a triangle at the rasterised depth (within the window below)
  Unmatched,  // rasterised, but the eye ray through the pixel centre finds no triangle there
              // (silhouette pixels where rasteriser and ray disagree): no reference normal
};
// Relative distance window in which a triangle hit along the eye ray counts as the rasterised
// surface: the depth buffer's distance is within ~16 float ulps (depth_prepass_test), i.e.
// 1e-6 relative; 1e-4 is wide enough for that and narrow enough to separate the 1 mm gap of
// "thin-gap" seen from 0.94 m (1e-3 relative).
// Far from the origin the rasterised depth itself errs by more: the vertex transform rounds
// world coordinates of size |eye| (viewProj · v in float, ~16 float ulps of |eye| + distance); the
// window adds kSurfaceMatchFarTerm · (|eye| + distance) = 32 · 2^-24 · (|eye| + distance).
inline constexpr double kSurfaceMatchTolerance = 1e-4;
inline constexpr double kSurfaceMatchFarTerm = 32.0 / 16777216.0;

// Per pixel, the true geometric surface: the eye ray through the pixel centre (x + 0.5, y + 0.5,
// as the rasteriser samples) is intersected with the scene, starting just before the rasterised
// distance, so that the triangle the rasteriser kept is found even where a nearer triangle's
// edge passes through the pixel centre.
struct ReferenceSurface {
  uint32_t width = 0, height = 0;
  glm::dvec3 eye{0.0};
  std::vector<SurfaceState> state;
  std::vector<glm::dvec3> position;  // Matched: the hit; Unmatched: worldFromDepth<double>; Sky: 0
  std::vector<glm::dvec3> normal;    // Matched: unit face normal facing the eye; else 0
  uint64_t matched = 0, unmatched = 0;
};
ReferenceSurface referenceSurface(const Bvh& bvh, const std::vector<float>& depth,
                                  const ReconstructionCamera<double>& cam);

}  // namespace hb
