// What an analysis frame measures of the indirect light (effects/indirect/indirect_effect.h): the frame's
// irradiance against the same photons ray traced (what the LDM approximation costs) and against
// the gathered reference (what photons, splats and directions cost), pixel by pixel on the same
// surface, with images; and where the split photons went.
#pragma once
#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "base/image_io.h"
#include "shared/gpu_types.h"

namespace hb {

// Errors of `mine` against `reference` (rgba per pixel, E in W/m²) on the luminance Y (Rec. 709)
// of every pixel: relMse = mean((Y − Y_ref)²)/mean(Y_ref²) (scale-free: 1 is an error as large as
// the light itself), totalRatio = ΣY/ΣY_ref (1: the image holds as much light), flip the mean
// LDR-FLIP of both images tone-mapped alike (indirectToImage with the reference's scale).
struct IndirectErrors {
  uint64_t pixels = 0;
  double relMse = 0, totalRatio = 0, flip = 0;
};
IndirectErrors indirectErrors(const std::vector<float>& mine, const std::vector<float>& reference, uint32_t width,
                              uint32_t height);
nlohmann::json toJson(const IndirectErrors& e);

// The exposure that maps the 99th percentile of the non-zero luminances of `rgba` to 1 (1 if none).
float indirectScale(const std::vector<float>& rgba);
// E·scale through ACES to sRGB (black: no indirect light).
ImageRGBA8 indirectToImage(const std::vector<float>& rgba, uint32_t width, uint32_t height, float scale);
// |Y − Y_ref|·scale in viridis from 0 to 0.5.
ImageRGBA8 indirectErrorToImage(const std::vector<float>& mine, const std::vector<float>& reference, uint32_t width,
                                uint32_t height, float scale);

// Two traces of the same photons (ldm against raytraced `b`, slot by slot): slots whose status
// agrees; where both were stored, how far apart they landed (median, 99th percentile, max: along
// the surface an LDM pixel's quantization moves a grazing photon far) and in how many slots `a`
// lies off b's landing plane by more than `tolerance` (the landing test's: another surface).
struct PhotonAgreement {
  uint64_t slots = 0, sameStatus = 0, bothStored = 0, offSurface = 0;
  double p50Distance = 0, p99Distance = 0, maxDistance = 0;
};
PhotonAgreement comparePhotons(const std::vector<gpu::Photon>& a, const std::vector<gpu::Photon>& b, double tolerance);

}  // namespace hb
