#include "analysis/reconstruction_accuracy.h"

#include <algorithm>
#include <cmath>

#include "analysis/analysis_pixels.h"
#include "base/errors.h"

namespace hb {

namespace {
constexpr double kRadToDeg = 57.29577951308232;

// Angle between two unit vectors, accurate near 0 and pi (acos loses half the digits there).
double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}
}  // namespace

NormalAccuracy normalAccuracy(const std::vector<float>& normals, const ReferenceSurface& surface) {
  const size_t pixels = surface.state.size();
  HB_ASSERT(normals.size() == 4 * pixels);
  NormalAccuracy a;
  a.angleDeg.assign(pixels, 0.0f);
  std::vector<double> angles;
  double sumAngle = 0, sumImage = 0;
  for (size_t i = 0; i < pixels; ++i) {
    if (surface.state[i] == SurfaceState::Sky) continue;
    if (surface.state[i] == SurfaceState::Unmatched) {
      a.withoutReference++;
      continue;
    }
    const glm::dvec3 g(normals[4 * i], normals[4 * i + 1], normals[4 * i + 2]);
    const double len = glm::length(g);
    if (!(len > 0.0) || !std::isfinite(len)) {
      a.withoutReconstruction++;
      continue;
    }
    const glm::dvec3 gu = g / len, r = surface.normal[i];
    const double angle = angleBetween(gu, r) * kRadToDeg;
    angles.push_back(angle);
    a.angleDeg[i] = float(angle);
    sumAngle += angle;
    // |(g*0.5+0.5) - (r*0.5+0.5)| = 0.5 |g - r| per channel; mean over r, g, b.
    const glm::dvec3 d = glm::abs(gu - r) * 0.5;
    sumImage += (d.x + d.y + d.z) / 3.0;
  }
  a.compared = angles.size();
  if (a.compared > 0) {
    a.meanAngleDeg = sumAngle / double(a.compared);
    a.meanImageDifference = sumImage / double(a.compared);
    a.maxAngleDeg = *std::max_element(angles.begin(), angles.end());
    // Nearest-rank 95th percentile: the smallest value with at least 95 % of the samples <= it.
    const size_t rank = size_t(std::ceil(0.95 * double(a.compared))) - 1;
    std::nth_element(angles.begin(), angles.begin() + rank, angles.end());
    a.p95AngleDeg = angles[rank];
  }
  return a;
}

nlohmann::json toJson(const NormalAccuracy& a) {
  return {{"compared", a.compared},
          {"without_reconstruction", a.withoutReconstruction},
          {"without_reference", a.withoutReference},
          {"mean_angle_deg", a.meanAngleDeg},
          {"p95_angle_deg", a.p95AngleDeg},
          {"max_angle_deg", a.maxAngleDeg},
          {"mean_image_difference", a.meanImageDifference}};
}

PositionAccuracy positionAccuracy(const std::vector<float>& positions, const std::vector<float>& depth,
                                  const ReconstructionCamera<double>& cam) {
  const size_t pixels = size_t(cam.width) * cam.height;
  HB_ASSERT(depth.size() == pixels && positions.size() == 4 * pixels);
  PositionAccuracy a;
  a.relative.assign(pixels, 0.0f);
  const glm::dvec3 eye(cam.viewInv[3]);
  double sum = 0, sumPlain = 0;
  for (uint32_t y = 0; y < cam.height; ++y)
    for (uint32_t x = 0; x < cam.width; ++x) {
      const size_t i = size_t(y) * cam.width + x;
      if (isSky(depth[i])) continue;
      const glm::dvec3 g(positions[4 * i], positions[4 * i + 1], positions[4 * i + 2]);
      if (!std::isfinite(g.x) || !std::isfinite(g.y) || !std::isfinite(g.z)) {
        a.nonFinite++;
        continue;
      }
      const glm::dvec3 ref = worldFromDepth<double>(cam, x, y, double(depth[i]));
      const glm::dvec3 plain = worldFromDepthPlain<double>(cam, x, y, double(depth[i]));
      const double rel = glm::length(g - ref) / glm::length(ref - eye);
      const double relPlain = glm::length(g - plain) / glm::length(plain - eye);
      a.relative[i] = float(rel);
      a.maxRelative = std::max(a.maxRelative, rel);
      a.maxRelativePlain = std::max(a.maxRelativePlain, relPlain);
      sum += rel;
      sumPlain += relPlain;
      a.compared++;
    }
  if (a.compared > 0) {
    a.meanRelative = sum / double(a.compared);
    a.meanRelativePlain = sumPlain / double(a.compared);
  }
  return a;
}

nlohmann::json toJson(const PositionAccuracy& a) {
  return {{"compared", a.compared},
          {"max_relative", a.maxRelative},
          {"mean_relative", a.meanRelative},
          {"max_relative_plain", a.maxRelativePlain},
          {"mean_relative_plain", a.meanRelativePlain},
          {"non_finite", a.nonFinite}};
}

}  // namespace hb
