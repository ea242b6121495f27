#include "effects/indirect/indirect_analysis.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "base/errors.h"
#include "reference/flip.h"

namespace hb {

namespace {
double luminance(const std::vector<float>& rgba, size_t i) {
  return 0.2126 * double(rgba[4 * i]) + 0.7152 * double(rgba[4 * i + 1]) + 0.0722 * double(rgba[4 * i + 2]);
}
uint32_t statusOf(const gpu::Photon& p) {
  uint32_t s;
  std::memcpy(&s, &p.normalStatus.w, 4);
  return s;
}
}  // namespace

float indirectScale(const std::vector<float>& rgba) {
  std::vector<double> y;
  for (size_t i = 0; i < rgba.size() / 4; ++i)
    if (const double v = luminance(rgba, i); v > 0.0 && std::isfinite(v)) y.push_back(v);
  if (y.empty()) return 1.0f;
  std::sort(y.begin(), y.end());
  return float(1.0 / y[size_t(0.99 * double(y.size() - 1))]);
}

ImageRGBA8 indirectToImage(const std::vector<float>& rgba, uint32_t width, uint32_t height, float scale) {
  HB_ASSERT(rgba.size() == size_t(width) * height * 4);
  ImageF hdr{width, height, 3, std::vector<float>(size_t(width) * height * 3)};
  for (size_t i = 0; i < size_t(width) * height; ++i)
    for (int c = 0; c < 3; ++c) hdr.px[3 * i + c] = rgba[4 * i + c] * scale;
  return toneMapToSrgb(hdr, 0.0f, ToneMapOperator::AcesFitted).image;
}

ImageRGBA8 indirectErrorToImage(const std::vector<float>& mine, const std::vector<float>& reference, uint32_t width,
                                uint32_t height, float scale) {
  std::vector<float> e(size_t(width) * height);
  for (size_t i = 0; i < e.size(); ++i) e[i] = float(std::abs(luminance(mine, i) - luminance(reference, i)) * scale);
  return errorMapToImage(e, width, height, 0.5f);
}

IndirectErrors indirectErrors(const std::vector<float>& mine, const std::vector<float>& reference, uint32_t width,
                              uint32_t height) {
  HB_ASSERT(mine.size() == reference.size() && mine.size() == size_t(width) * height * 4);
  IndirectErrors r;
  double se = 0, s2 = 0, sum = 0, sumRef = 0;
  for (size_t i = 0; i < size_t(width) * height; ++i) {
    const double a = luminance(mine, i), b = luminance(reference, i);
    se += (a - b) * (a - b);
    s2 += b * b;
    sum += a;
    sumRef += b;
  }
  r.pixels = uint64_t(width) * height;
  r.relMse = s2 > 0.0 ? se / s2 : 0.0;
  r.totalRatio = sumRef > 0.0 ? sum / sumRef : 0.0;
  const float scale = indirectScale(reference);
  r.flip = ldrFlip(indirectToImage(reference, width, height, scale), indirectToImage(mine, width, height, scale)).mean;
  return r;
}

nlohmann::json toJson(const IndirectErrors& e) {
  return {{"pixels", e.pixels}, {"rel_mse", e.relMse}, {"total_ratio", e.totalRatio}, {"flip", e.flip}};
}

PhotonAgreement comparePhotons(const std::vector<gpu::Photon>& a, const std::vector<gpu::Photon>& b, double tolerance) {
  HB_ASSERT(a.size() == b.size());
  PhotonAgreement r;
  r.slots = a.size();
  std::vector<double> d;
  for (size_t i = 0; i < a.size(); ++i) {
    const uint32_t sa = statusOf(a[i]), sb = statusOf(b[i]);
    r.sameStatus += sa == sb;
    if (sa != gpu::kPhotonStored || sb != gpu::kPhotonStored) continue;
    ++r.bothStored;
    const glm::dvec3 pa(a[i].positionFluxR), pb(b[i].positionFluxR), nb(b[i].normalStatus);
    d.push_back(glm::length(pa - pb));
    r.offSurface += std::abs(glm::dot(pa - pb, nb)) > tolerance;
  }
  if (!d.empty()) {
    std::sort(d.begin(), d.end());
    r.p50Distance = d[size_t(0.5 * double(d.size() - 1))];
    r.p99Distance = d[size_t(0.99 * double(d.size() - 1))];
    r.maxDistance = d.back();
  }
  return r;
}

}  // namespace hb
