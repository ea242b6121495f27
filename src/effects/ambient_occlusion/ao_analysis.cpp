#include "effects/ambient_occlusion/ao_analysis.h"

#include <algorithm>
#include <cmath>

#include "base/errors.h"
#include "reference/flip.h"

namespace hb {

ImageRGBA8 aoToImage(const std::vector<float>& ao, uint32_t width, uint32_t height) {
  HB_ASSERT(ao.size() == size_t(width) * height);
  ImageRGBA8 img{width, height, std::vector<uint8_t>(size_t(width) * height * 4, 255)};
  for (size_t i = 0; i < ao.size(); ++i) {
    uint8_t* p = &img.px[4 * i];
    if (ao[i] == -1.0f) {  // gpu::kAoSky
      p[0] = 20, p[1] = 30, p[2] = 90;
    } else if (!(ao[i] >= 0.0f)) {  // no normal (or not finite)
      p[0] = 255, p[1] = 0, p[2] = 255;
    } else {
      const uint8_t g = uint8_t(std::lround(255.0 * std::clamp(double(ao[i]), 0.0, 1.0)));
      p[0] = p[1] = p[2] = g;
    }
  }
  return img;
}

ImageRGBA8 aoErrorToImage(const std::vector<float>& ao, const std::vector<float>& reference, uint32_t width,
                          uint32_t height, float scale) {
  std::vector<float> e(ao.size(), 0.0f);
  for (size_t i = 0; i < ao.size(); ++i)
    if (ao[i] >= 0.0f && reference[i] >= 0.0f) e[i] = std::abs(ao[i] - reference[i]);
  return errorMapToImage(e, width, height, scale);
}

AoErrors aoErrors(const std::vector<float>& ao, const std::vector<float>& reference, uint32_t width, uint32_t height) {
  HB_ASSERT(ao.size() == reference.size() && ao.size() == size_t(width) * height);
  AoErrors r;
  std::vector<double> abs;
  double sum = 0, sum2 = 0, signedSum = 0;
  uint64_t over = 0;
  for (size_t i = 0; i < ao.size(); ++i) {
    if (!(ao[i] >= 0.0f && reference[i] >= 0.0f)) continue;
    const double d = double(ao[i]) - double(reference[i]);
    abs.push_back(std::abs(d));
    sum += std::abs(d);
    sum2 += d * d;
    signedSum += d;
    over += std::abs(d) > 0.1;
  }
  r.pixels = abs.size();
  if (abs.empty()) return r;
  const double n = double(abs.size());
  r.mae = sum / n;
  r.rmse = std::sqrt(sum2 / n);
  r.bias = signedSum / n;
  r.over01 = double(over) / n;
  std::sort(abs.begin(), abs.end());
  r.p95 = abs[size_t(0.95 * (n - 1))];
  r.maxAbs = abs.back();
  // FLIP of the AO images as grey pictures (the error a viewer sees); pixels left out are equal in
  // both (the same sky and magenta) and add nothing.
  std::vector<float> a = ao, b = reference;
  for (size_t i = 0; i < a.size(); ++i)
    if (!(a[i] >= 0.0f && b[i] >= 0.0f)) a[i] = b[i] = -1.0f;
  r.flip = ldrFlip(aoToImage(b, width, height), aoToImage(a, width, height)).mean;
  return r;
}

nlohmann::json toJson(const AoErrors& e) {
  return {{"pixels", e.pixels},
          {"mae", e.mae},
          {"rmse", e.rmse},
          {"bias", e.bias},
          {"p95", e.p95},
          {"max", e.maxAbs},
          {"share_over_0_1", e.over01},
          {"flip", e.flip}};
}

}  // namespace hb
