// LDR-FLIP: a perceptual per-pixel difference between two sRGB images, after Andersson, Nilsson,
// Akenine-Möller, Oskarsson, Åström and Fairchild, "FLIP: A Difference Evaluator for Alternating
// Images", Proc. ACM Comput. Graph. Interact. Tech. 3(2), 2020 (HPG 2020). Our own implementation
// of the published algorithm; constants as in the paper (listed in flip.cpp).
#pragma once
#include <numbers>

#include "base/image_io.h"

namespace hb {

// Pixels per degree of visual angle for a monitor `widthM` metres wide showing `resolutionPx`
// pixels across, seen from `distanceM` metres: distance * (resolution/width) * pi/180 (the paper's
// small-angle form).
constexpr double pixelsPerDegree(double distanceM, double widthM, double resolutionPx) {
  return distanceM * (resolutionPx / widthM) * std::numbers::pi / 180.0;
}

// The paper's default viewing setup: 0.7 m from a 0.7 m wide 3840-pixel monitor, ~67.02 ppd.
constexpr double kDefaultPpd = pixelsPerDegree(0.7, 0.7, 3840);

struct FlipResult {
  ImageF errorMap;                             // 1 channel, values in [0, 1]
  double mean = 0, p50 = 0, p95 = 0, max = 0;  // percentiles interpolate linearly between ranks
};

// Per-pixel LDR-FLIP error of `test` against `reference` (alpha ignored), viewed at `ppd`
// pixels per degree. Identical images give exactly 0 everywhere.
// Throws InputError when the two images differ in size; preconditions: ppd > 0, images non-empty.
FlipResult ldrFlip(const ImageRGBA8& reference, const ImageRGBA8& test, double ppd = kDefaultPpd);

// Radius in pixels beyond which one pixel cannot influence another's FLIP error: the larger of
// the CSF filter radius and the feature filter radius at `ppd`.
int flipSupportRadius(double ppd);

}  // namespace hb
