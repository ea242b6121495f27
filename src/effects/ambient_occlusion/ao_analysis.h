// What an analysis frame measures of ambient occlusion (effects/ambient_occlusion/ao_effect.h): the frame's
// AO against the same directions ray traced (what the LDM approximation costs) and against the
// converged Monte Carlo reference (what the direction count costs), pixel by pixel on the same
// surface, with images of the AO and of its error.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "base/image_io.h"

namespace hb {

// Errors of `ao` against `reference` over the pixels where both hold an AO value (>= 0: sky and
// pixels without a normal are left out). bias is the signed mean (positive: `ao` lets more light
// through than the reference: light leaks); p95 of |error|; over01 the share of pixels off by more
// than 0.1; flip the mean LDR-FLIP of the two AO images (grey = AO) at the default viewing setup.
struct AoErrors {
  uint64_t pixels = 0;
  double mae = 0, rmse = 0, bias = 0, p95 = 0, maxAbs = 0, over01 = 0, flip = 0;
};
// Preconditions: ao.size() == reference.size() == width·height.
AoErrors aoErrors(const std::vector<float>& ao, const std::vector<float>& reference, uint32_t width, uint32_t height);
nlohmann::json toJson(const AoErrors& e);

// Grey = AO (white: unoccluded), the sky dark blue, pixels without a normal magenta.
ImageRGBA8 aoToImage(const std::vector<float>& ao, uint32_t width, uint32_t height);
// |ao − reference| in viridis from 0 to `scale`; pixels not compared black.
ImageRGBA8 aoErrorToImage(const std::vector<float>& ao, const std::vector<float>& reference, uint32_t width,
                          uint32_t height, float scale);

}  // namespace hb
