#include "analysis/reference_surface.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "analysis/analysis_pixels.h"
#include "base/errors.h"
#include "base/parallel.h"

namespace hb {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

ReferenceSurface referenceSurface(const Bvh& bvh, const std::vector<float>& depth,
                                  const ReconstructionCamera<double>& cam) {
  const size_t pixels = size_t(cam.width) * cam.height;
  HB_ASSERT(depth.size() == pixels);
  ReferenceSurface s;
  s.width = cam.width;
  s.height = cam.height;
  s.eye = glm::dvec3(cam.viewInv[3]);
  s.state.assign(pixels, SurfaceState::Sky);
  s.position.assign(pixels, glm::dvec3(0.0));
  s.normal.assign(pixels, glm::dvec3(0.0));
  parallelFor(cam.height, [&](size_t row) {
    const uint32_t y = uint32_t(row);
    for (uint32_t x = 0; x < cam.width; ++x) {
      const size_t i = size_t(y) * cam.width + x;
      if (isSky(depth[i])) continue;
      // The eye ray through the pixel centre, scaled so that its view-space z step is -1: then
      // the ray parameter equals the view distance -z = D / (depth + C) (camera.h).
      const double ndcX = std::fma((x + 0.5) / cam.width, 2.0, -1.0);
      const double ndcY = std::fma((y + 0.5) / cam.height, 2.0, -1.0);
      const glm::dvec3 dir(cam.viewInv * glm::dvec4(ndcX / cam.a, ndcY / cam.b, -1.0, 0.0));
      const double tDepth = cam.d / (double(depth[i]) + cam.c);
      double t;
      uint32_t tri;
      // The window: kSurfaceMatchTolerance relative, plus the rasteriser's absolute error far from
      // the origin (vertex − eye cancels in float: ~16 u (|eye| + distance), doubled).
      const double window = kSurfaceMatchTolerance * tDepth + kSurfaceMatchFarTerm * (glm::length(s.eye) + tDepth);
      const bool hit = bvh.closestHit(s.eye, dir, std::max(0.0, tDepth - window), kInf, t, tri);
      if (hit && t <= tDepth + window) {
        const BvhTriangle& T = bvh.input(tri);
        s.position[i] = s.eye + t * dir;
        glm::dvec3 n = glm::normalize(glm::cross(T.v1 - T.v0, T.v2 - T.v0));
        if (glm::dot(n, s.eye - s.position[i]) < 0.0) n = -n;
        s.normal[i] = n;
        s.state[i] = SurfaceState::Matched;
      } else {
        s.position[i] = worldFromDepth<double>(cam, x, y, double(depth[i]));
        s.state[i] = SurfaceState::Unmatched;
      }
    }
  });
  for (SurfaceState st : s.state) {
    s.matched += st == SurfaceState::Matched;
    s.unmatched += st == SurfaceState::Unmatched;
  }
  return s;
}

}  // namespace hb
