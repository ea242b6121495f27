// How accurate the GPU's reconstructed normals and world positions are, against double-precision
// references. Images are row-major, width × height, top row first; depth 0 = sky.
#pragma once
#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis/reference_surface.h"
#include "reference/reconstruct_ref.h"

namespace hb {

// Reconstructed normals (GPU, xyzw per pixel, 0 = none) against the reference surface's normals.
struct NormalAccuracy {
  uint64_t compared = 0;               // matched pixels with a reconstructed normal
  uint64_t withoutReconstruction = 0;  // matched pixels where the GPU gave no normal
  uint64_t withoutReference = 0;       // unmatched pixels
  double meanAngleDeg = 0, p95AngleDeg = 0, maxAngleDeg = 0;
  // Mean over compared pixels of the normal images' difference: rgb = n*0.5 + 0.5, per pixel the
  // mean over r, g, b of |rgb_a − rgb_b|, in [0, 1]. This is our reading of the thesis's "mean
  // difference" of Figure 5.3 (0.07975 naive, 0.02264 improved); the thesis does not define it.
  double meanImageDifference = 0;
  std::vector<float> angleDeg;  // per pixel, 0 where not compared
};
NormalAccuracy normalAccuracy(const std::vector<float>& normals, const ReferenceSurface& surface);
nlohmann::json toJson(const NormalAccuracy& acc);

// GPU world positions (xyzw, w = 1 where not sky) against worldFromDepth<double> (Alg. 4.1) and
// worldFromDepthPlain<double> from the same depth values: |p_gpu − p_cpu| / |p_cpu − eye|.
struct PositionAccuracy {
  uint64_t compared = 0;
  double maxRelative = 0, meanRelative = 0;            // against Alg. 4.1 in double
  double maxRelativePlain = 0, meanRelativePlain = 0;  // against the plain inverse in double
  uint64_t nonFinite = 0;                              // GPU positions with NaN/Inf (never compared)
  std::vector<float> relative;                         // per pixel (Alg. 4.1), 0 for sky
};
PositionAccuracy positionAccuracy(const std::vector<float>& positions, const std::vector<float>& depth,
                                  const ReconstructionCamera<double>& cam);
nlohmann::json toJson(const PositionAccuracy& acc);

}  // namespace hb
