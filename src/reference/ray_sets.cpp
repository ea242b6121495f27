#include "reference/ray_sets.h"

#include <algorithm>
#include <cmath>

#include "base/parallel.h"
#include "reference/ldm_ref.h"

namespace hb {

namespace {

RayRecord record(const glm::dvec3& origin, double tMin, const glm::dvec3& dir, double tMax) {
  return {{float(origin.x), float(origin.y), float(origin.z)},
          float(tMin),
          {float(dir.x), float(dir.y), float(dir.z)},
          float(tMax)};
}
glm::dvec3 originOf(const RayRecord& r) { return {r.origin[0], r.origin[1], r.origin[2]}; }
glm::dvec3 dirOf(const RayRecord& r) { return {r.dir[0], r.dir[1], r.dir[2]}; }

// splitmix64 (Steele, Lea and Flood 2014): a well-mixed value of (seed, index), so each ray's
// directions do not depend on which thread made it.
uint64_t mix(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}
double unitOf(uint64_t x) { return double(x >> 11) * 0x1p-53; }

// The point a camera ray hit, moved `offset` off its triangle along the geometric normal turned
// towards the ray's origin; that normal in `n`.
glm::dvec3 offsetHit(const Bvh& bvh, const RayRecord& ray, double t, uint32_t triangle, double offset, glm::dvec3& n) {
  const BvhTriangle& tri = bvh.input(triangle);
  n = glm::normalize(glm::cross(tri.v1 - tri.v0, tri.v2 - tri.v0));
  const glm::dvec3 d = dirOf(ray);
  if (glm::dot(n, d) > 0.0) n = -n;
  return originOf(ray) + t * d + offset * n;
}

template <class Make>
std::vector<RayRecord> fromHits(const std::vector<RayRecord>& camera, const RayHits& hits, Make make) {
  std::vector<size_t> at;  // the camera rays that hit, in order
  for (size_t i = 0; i < camera.size(); ++i)
    if (hits.t[i] >= 0.0) at.push_back(i);
  std::vector<RayRecord> out(at.size());
  parallelFor(at.size(), [&](size_t k) { out[k] = make(k, at[k]); });
  return out;
}

}  // namespace

RayView rayViewOf(const Camera& camera, uint32_t width, uint32_t height) {
  const glm::dmat4 toWorld = glm::inverse(glm::dmat4(camera.view));
  const double tanY = std::tan(0.5 * double(camera.yfov)), aspect = double(width) / double(height);
  return {glm::dvec3(toWorld[3]),
          -glm::dvec3(toWorld[2]),
          glm::dvec3(toWorld[0]) * tanY * aspect,
          glm::dvec3(toWorld[1]) * tanY,
          width,
          height};
}

nlohmann::json toJson(const RayView& v, const Camera& camera) {
  const glm::dmat4 toWorld = glm::inverse(glm::dmat4(camera.view));
  const glm::dvec3 up(toWorld[1]);
  return {{"eye", {v.eye.x, v.eye.y, v.eye.z}},
          {"forward", {v.forward.x, v.forward.y, v.forward.z}},
          {"up", {up.x, up.y, up.z}},
          {"yfov_deg", double(camera.yfov) * 180.0 / 3.14159265358979323846},
          {"width", v.width},
          {"height", v.height},
          {"pixel",
           "centres: direction normalize(forward + ndc.x * right - ndc.y * up), ndc = (pixel + 0.5) / size * 2 - 1"}};
}

std::vector<RayRecord> cameraRays(const RayView& v) {
  std::vector<RayRecord> rays(size_t(v.width) * v.height);
  for (uint32_t y = 0; y < v.height; ++y)
    for (uint32_t x = 0; x < v.width; ++x) {
      const double nx = (x + 0.5) / v.width * 2.0 - 1.0, ny = (y + 0.5) / v.height * 2.0 - 1.0;
      rays[size_t(y) * v.width + x] = record(v.eye, 0.0, glm::normalize(v.forward + nx * v.right - ny * v.up), 1e30);
    }
  return rays;
}

size_t RayHits::hits() const {
  return size_t(std::count_if(t.begin(), t.end(), [](double x) { return x >= 0.0; }));
}

RayHits traceOnCpu(const Bvh& bvh, const std::vector<RayRecord>& rays, bool anyHit) {
  RayHits h;
  h.t.assign(rays.size(), -1.0);
  h.triangle.assign(rays.size(), ~0u);
  parallelFor(rays.size(), [&](size_t i) {
    const RayRecord& r = rays[i];
    double t = -1.0;
    uint32_t tri = ~0u;
    if (anyHit) {
      if (bvh.occluded(originOf(r), dirOf(r), r.tMin, r.tMax)) t = 0.0;
    } else if (!bvh.closestHit(originOf(r), dirOf(r), r.tMin, r.tMax, t, tri)) {
      t = -1.0;
    }
    h.t[i] = t;
    h.triangle[i] = tri;
  });
  return h;
}

std::vector<RayRecord> aoRays(const Bvh& bvh, const std::vector<RayRecord>& camera, const RayHits& hits,
                              const SecondaryParams& p) {
  return fromHits(camera, hits, [&](size_t k, size_t i) {
    glm::dvec3 n;
    const glm::dvec3 o = offsetHit(bvh, camera[i], hits.t[i], hits.triangle[i], p.offset, n);
    // Cosine-distributed about n (Malley's method) in the references' basis around n.
    const uint64_t h = mix(p.seed ^ mix(k));
    const double u1 = unitOf(h), u2 = unitOf(mix(h)), r = std::sqrt(u1), phi = 2.0 * 3.14159265358979323846 * u2;
    glm::dvec3 t1, t2;
    orthonormalBasis(n, t1, t2);
    const glm::dvec3 d = r * std::cos(phi) * t1 + r * std::sin(phi) * t2 + std::sqrt(std::max(0.0, 1.0 - u1)) * n;
    return record(o, 0.0, glm::normalize(d), p.tMax);
  });
}

std::vector<RayRecord> shadowRays(const Bvh& bvh, const std::vector<RayRecord>& camera, const RayHits& hits,
                                  const SecondaryParams& p) {
  return fromHits(camera, hits, [&](size_t, size_t i) {
    glm::dvec3 n;
    const glm::dvec3 o = offsetHit(bvh, camera[i], hits.t[i], hits.triangle[i], p.offset, n);
    const glm::dvec3 toLight = p.light - o;
    const double d = glm::length(toLight);
    return record(o, 0.0, toLight / d, d);
  });
}

}  // namespace hb
