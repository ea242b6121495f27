#include "analysis/primary_analysis.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "reference/raster3d_ref.h"

namespace hb {

namespace {

// Smallest barycentric coordinate of the ray's hit with the triangle's plane (negative outside);
// -inf when the ray is parallel to the plane.
double barycentricMargin(const BvhTriangle& tri, const glm::dvec3& org, const glm::dvec3& dir) {
  const glm::dvec3 e1 = tri.v1 - tri.v0, e2 = tri.v2 - tri.v0, pv = glm::cross(dir, e2);
  const double det = glm::dot(e1, pv);
  if (det == 0.0) return -INFINITY;
  const glm::dvec3 tv = org - tri.v0;
  const double u = glm::dot(tv, pv) / det;
  const double v = glm::dot(dir, glm::cross(tv, e1)) / det;
  return std::min({u, v, 1.0 - u - v});
}

// The ray of pixel (x, y) in double from the shader's float constants (camera_ray.glsl.inc, the
// same formulas); false where the view has no ray (outside the paraboloid's disk).
bool cameraRay(const gpu::Raster3dConstants& c, uint32_t xi, uint32_t yi, glm::dvec3& org, glm::dvec3& dir) {
  const double x = xi, y = yi;
  const glm::dvec3 right(c.right), up(c.up), forward(c.forward);
  org = glm::dvec3(c.eye);
  switch (c.projection) {
    case gpu::kProjectionOrthographic:
      org += glm::dvec3(c.origin0) + x * glm::dvec3(c.originX) + y * glm::dvec3(c.originY);
      dir = forward;
      return true;
    case gpu::kProjectionParaboloid: {
      const double u = (x - double(c.view.x)) * double(c.view.z), v = (double(c.view.y) - y) * double(c.view.z);
      if (u * u + v * v > 1.0) return false;
      dir = glm::normalize(u * right + v * up + (0.5 - 0.5 * (u * u + v * v)) * forward);
      return true;
    }
    case gpu::kProjectionLatlong: {
      const double pi = 3.14159265358979323846;
      const double phi = (x + 0.5) * double(c.view.x) - pi, theta = 0.5 * pi - (y + 0.5) * double(c.view.y);
      dir = std::cos(theta) * std::sin(phi) * right + std::sin(theta) * up + std::cos(theta) * std::cos(phi) * forward;
      return true;
    }
    default: dir = glm::dvec3(c.rayD0) + x * glm::dvec3(c.rayDx) + y * glm::dvec3(c.rayDy); return true;
  }
}

}  // namespace

PrimaryComparison comparePrimary(const Bvh& bvh, const std::vector<uint64_t>& vis, const gpu::Raster3dConstants& c) {
  PrimaryComparison r;
  const double zn = c.depth.x, zf = c.depth.y;
  std::vector<double> rel;
  for (uint32_t y = 0; y < c.height; ++y)
    for (uint32_t x = 0; x < c.width; ++x) {
      const uint64_t key = vis[size_t(y) * c.width + x];
      glm::dvec3 eye, dir;
      const bool hasRay = cameraRay(c, x, y, eye, dir);
      double tCpu = 0;
      uint32_t idCpu = 0;
      const bool cpuHit = hasRay && bvh.closestHit(eye, dir, zn, zf, tCpu, idCpu);
      const bool gpuHit = key != ~0ull;
      const uint32_t idGpu = uint32_t(key & 0xFFFFFFFFu);
      const double tGpu = gpuHit ? double(std::bit_cast<float>(uint32_t(key >> 32))) : 0.0;
      ++r.pixels;
      auto nearEdge = [&](uint32_t id) { return std::abs(barycentricMargin(bvh.input(id), eye, dir)) <= kTieMargin; };
      const double offset = glm::length(eye - glm::dvec3(c.eye));  // 0 but for orthographic views
      if (cpuHit && gpuHit) {
        ++r.bothHit;
        if (idCpu == idGpu) {
          ++r.idsEqual;
          rel.push_back(std::abs(tGpu - tCpu) / tCpu);
        } else {
          ++r.idMismatches;
          const bool tie =
              std::abs(tGpu - tCpu) <= kTieDepth * tieScale(tCpu, offset) || nearEdge(idCpu) || nearEdge(idGpu);
          r.notTies += !tie;
        }
      } else if (cpuHit) {
        ++r.holes;
        r.notTies += !(nearEdge(idCpu) || std::abs(tCpu - zn) <= kTieDepth * tieScale(zn, offset) ||
                       std::abs(tCpu - zf) <= kTieDepth * zf);
      } else if (gpuHit) {
        ++r.spurious;
        r.notTies += !(nearEdge(idGpu) || std::abs(tGpu - zn) <= kTieDepth * tieScale(zn, offset) ||
                       std::abs(tGpu - zf) <= kTieDepth * zf);
      }
    }
  if (!rel.empty()) {
    std::sort(rel.begin(), rel.end());
    r.depthRelP999 = rel[std::min(rel.size() - 1, size_t(std::ceil(0.999 * double(rel.size()))) - 1)];
    r.depthRelMax = rel.back();
  }
  return r;
}

CoverageComparison compareCoverage(const Scene& scene, const gpu::Raster3dConstants& c,
                                   const std::vector<uint32_t>& method) {
  Raster3dView view;
  view.eye = glm::vec3(c.eye);
  view.d0 = glm::vec3(c.rayD0);
  view.dx = glm::vec3(c.rayDx);
  view.dy = glm::vec3(c.rayDy);
  view.width = c.width;
  view.height = c.height;
  view.znear = c.depth.x;
  view.zfar = c.depth.y;
  const std::vector<glm::vec3> positions = scene.worldTriangles();
  std::vector<uint32_t> indices(positions.size());
  for (size_t i = 0; i < indices.size(); ++i) indices[i] = uint32_t(i);
  const Raster3dResult exact = rasterize3d(view, positions, indices);
  CoverageComparison r;
  for (size_t i = 0; i < exact.coverage.size() && i < method.size(); ++i) {
    ++r.pixels;
    r.coveredPixels += exact.coverage[i] > 0;
    r.doubleCovers += method[i] > exact.coverage[i];
    r.holes += method[i] < exact.coverage[i];
  }
  return r;
}

nlohmann::json toJson(const CoverageComparison& c) {
  return {{"reference",
           "exact 3D rasterization on the CPU (reference/raster3d_ref: same float rays and vertices, "
           "exact signs, same tie rule), coverage counted additively per pixel at every depth"},
          {"pixels", c.pixels},
          {"covered_pixels", c.coveredPixels},
          {"double_covers", c.doubleCovers},
          {"holes", c.holes}};
}

nlohmann::json toJson(const PrimaryComparison& c) {
  return {{"reference", "double-precision ray cast per pixel (watertight BVH), same rays, t in [znear, zfar]"},
          {"pixels", c.pixels},
          {"both_hit", c.bothHit},
          {"ids_equal", c.idsEqual},
          {"ids_equal_fraction", c.bothHit ? double(c.idsEqual) / double(c.bothHit) : 1.0},
          {"id_mismatches", c.idMismatches},
          {"holes", c.holes},
          {"spurious", c.spurious},
          {"not_ties", c.notTies},
          {"tie_margin_barycentric", kTieMargin},
          {"depth_rel_error_p999", c.depthRelP999},
          {"depth_rel_error_max", c.depthRelMax}};
}

}  // namespace hb
