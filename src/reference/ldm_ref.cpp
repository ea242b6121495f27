#include "reference/ldm_ref.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>

#include "base/errors.h"

namespace hb {

void orthonormalBasis(const glm::dvec3& f, glm::dvec3& b1, glm::dvec3& b2) {
  const double s = f.z >= 0.0 ? 1.0 : -1.0;
  const double a = -1.0 / (s + f.z);  // |s + f.z| >= 1: no cancellation, no division by ~0
  const double b = f.x * f.y * a;
  b1 = glm::dvec3(1.0 + s * f.x * f.x * a, s * b, -s * f.x);
  b2 = glm::dvec3(b, s + f.y * f.y * a, -f.y);
}

LdmView ldmView(const glm::dvec3& dir, const glm::dvec3& centre, double radius, uint32_t resolution) {
  HB_ASSERT(std::abs(glm::length(dir) - 1.0) <= 1e-9);
  HB_ASSERT(radius > 0.0 && std::isfinite(radius));
  HB_ASSERT(resolution >= 1);
  LdmView v{dir, {}, {}, centre, radius, resolution};
  orthonormalBasis(-dir, v.right, v.up);
  return v;
}

glm::dvec3 ldmPixelOrigin(const LdmView& view, uint32_t i, uint32_t j) {
  HB_ASSERT(i < view.resolution && j < view.resolution);
  const double r = view.resolution;
  const double a = (2.0 * (i + 0.5) / r - 1.0) * view.radius;
  const double b = (1.0 - 2.0 * (j + 0.5) / r) * view.radius;
  return view.centre + a * view.right + b * view.up - view.radius * view.dir;
}

bool ldmProject(const LdmView& view, const glm::dvec3& p, uint32_t& i, uint32_t& j) {
  const glm::dvec3 d = p - view.centre;
  const double r = view.resolution;
  const double fx = (glm::dot(d, view.right) / view.radius + 1.0) * 0.5 * r;
  const double fy = (1.0 - glm::dot(d, view.up) / view.radius) * 0.5 * r;
  if (!(fx >= 0.0 && fx < r && fy >= 0.0 && fy < r)) return false;  // NaN too
  i = std::min(uint32_t(fx), view.resolution - 1);
  j = std::min(uint32_t(fy), view.resolution - 1);
  return true;
}

double ldmDepth(const LdmView& view, const glm::dvec3& p) { return glm::dot(p - view.centre, view.dir) + view.radius; }

LdmSphere ldmBoundingSphere(const Bvh& bvh) {
  if (bvh.triangles().empty()) return {glm::dvec3(0.0), 1.0};
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const auto& t : bvh.triangles()) {
    lo = glm::min(lo, glm::min(t.v0, glm::min(t.v1, t.v2)));
    hi = glm::max(hi, glm::max(t.v0, glm::max(t.v1, t.v2)));
  }
  return {0.5 * (lo + hi), std::max(0.5 * glm::length(hi - lo) * (1.0 + 1e-6), 1e-300)};
}

std::span<const double> ExactLdm::pixel(uint32_t i, uint32_t j) const {
  HB_ASSERT(i < view.resolution && j < view.resolution);
  const size_t k = size_t(j) * view.resolution + i;
  return std::span<const double>(depths).subspan(first[k], first[k + 1] - first[k]);
}

std::vector<double> exactLdmPixel(const Bvh& bvh, const LdmView& view, uint32_t i, uint32_t j) {
  std::vector<BvhHit> hits;
  // The line starts at depth 0, dir is unit: t is the depth.
  bvh.allHits(ldmPixelOrigin(view, i, j), view.dir, 0.0, 2.0 * view.radius, hits);
  // Hits of one point through triangles sharing an edge differ by rounding of t only (a few ulps
  // of the coordinates); 1e-9 of the depth range is far above that for scenes within ~1e5 radii
  // of the origin, and far below the GPU comparison's 1e-4 m.
  const double tol = 1e-9 * 2.0 * view.radius;
  std::vector<double> out;
  for (size_t k = 0; k < hits.size();) {
    bool front = false, back = false;
    double tFront = 0.0, tBack = 0.0;
    size_t e = k;
    for (; e < hits.size() && hits[e].t - hits[k].t <= tol; ++e) {
      const BvhTriangle& tri = bvh.input(hits[e].triangle);
      const bool facesViewer = glm::dot(glm::cross(tri.v1 - tri.v0, tri.v2 - tri.v0), view.dir) < 0.0;
      if (facesViewer && !front) front = true, tFront = hits[e].t;
      if (!facesViewer && !back) back = true, tBack = hits[e].t;
    }
    if (front && back) {
      out.push_back(std::min(tFront, tBack));
      out.push_back(std::max(tFront, tBack));
    } else {
      out.push_back(front ? tFront : tBack);
    }
    k = e;
  }
  return out;
}

ExactLdm exactLdm(const Bvh& bvh, const LdmView& view) {
  ExactLdm ldm{view, {}, {}};
  const uint32_t r = view.resolution;
  ldm.first.reserve(size_t(r) * r + 1);
  ldm.first.push_back(0);
  for (uint32_t j = 0; j < r; ++j)
    for (uint32_t i = 0; i < r; ++i) {
      const std::vector<double> list = exactLdmPixel(bvh, view, i, j);
      ldm.depths.insert(ldm.depths.end(), list.begin(), list.end());
      HB_ASSERT(ldm.depths.size() <= std::numeric_limits<uint32_t>::max());
      ldm.first.push_back(uint32_t(ldm.depths.size()));
    }
  return ldm;
}

LdmNodeStats ldmNodeStats(const ExactLdm& ldm) {
  LdmNodeStats s;
  std::vector<uint32_t> counts(ldm.first.size() - 1);
  for (size_t k = 0; k < counts.size(); ++k) counts[k] = ldm.first[k + 1] - ldm.first[k];
  s.pixels = counts.size();
  s.nodes = ldm.depths.size();
  if (counts.empty()) return s;
  s.mean = double(s.nodes) / double(s.pixels);
  std::sort(counts.begin(), counts.end());
  // Nearest rank: the ceil(0.99 P)-th smallest count (1-based).
  const size_t rank = size_t(std::ceil(0.99 * double(counts.size())));
  s.p99 = counts[std::max<size_t>(rank, 1) - 1];
  s.max = counts.back();
  return s;
}

LdmTrace ldmTraceList(std::span<const double> sorted, double zx, double bias) {
  HB_ASSERT(bias >= 0.0);
  LdmTrace r;
  // First entry >= z_x - bias; the one before it is the last entry below.
  auto it = std::lower_bound(sorted.begin(), sorted.end(), zx - bias);
  if (it != sorted.begin()) r.backward = {true, zx - *(it - 1)};
  while (it != sorted.end() && *it <= zx + bias) ++it;  // x's own surface
  if (it != sorted.end()) r.forward = {true, *it - zx};
  return r;
}

LdmTrace ldmTrace(const ExactLdm& ldm, const glm::dvec3& x, double bias) {
  uint32_t i, j;
  if (!ldmProject(ldm.view, x, i, j)) return {};
  return ldmTraceList(ldm.pixel(i, j), ldmDepth(ldm.view, x), bias);
}

namespace {

void checkAoArguments(const glm::dvec3& n, double dMax, double tMin) {
  HB_ASSERT(std::abs(glm::length(n) - 1.0) <= 1e-9);
  HB_ASSERT(tMin >= 0.0 && tMin < dMax);
}

// V = 0 when a hit lies within (tMin, dMax]: Bvh::occluded tests the closed interval, so start at
// the next double above tMin.
bool occludedWithin(const Bvh& bvh, const glm::dvec3& p, const glm::dvec3& w, double dMax, double tMin) {
  return bvh.occluded(p, w, std::nextafter(tMin, std::numeric_limits<double>::infinity()), dMax);
}

// One term of eq. 2 from a trace: the hit in n's hemisphere counts when it is within dMax.
double ldmTerm(const LdmTrace& tr, double c, double dMax) {
  const LdmHit& h = c > 0.0 ? tr.forward : tr.backward;
  const bool occluded = h.hit && h.distance <= dMax;
  return occluded ? 0.0 : std::abs(c);
}

}  // namespace

double aoRayTraced(const Bvh& bvh, const glm::dvec3& p, const glm::dvec3& n, const std::vector<glm::dvec3>& dirs,
                   double dMax, double tMin) {
  checkAoArguments(n, dMax, tMin);
  HB_ASSERT(!dirs.empty());
  double sum = 0.0;
  for (const glm::dvec3& v : dirs) {
    const double c = glm::dot(n, v);
    if (c == 0.0) continue;
    if (!occludedWithin(bvh, p, c > 0.0 ? v : -v, dMax, tMin)) sum += std::abs(c);
  }
  return 2.0 * sum / double(dirs.size());
}

double aoLdm(const std::vector<ExactLdm>& ldms, const glm::dvec3& p, const glm::dvec3& n, double dMax, double bias) {
  checkAoArguments(n, dMax, bias);
  HB_ASSERT(!ldms.empty());
  double sum = 0.0;
  for (const ExactLdm& ldm : ldms) {
    const double c = glm::dot(n, ldm.view.dir);
    if (c == 0.0) continue;
    sum += ldmTerm(ldmTrace(ldm, p, bias), c, dMax);
  }
  return 2.0 * sum / double(ldms.size());
}

double aoLdm(const Bvh& bvh, const std::vector<LdmView>& views, const glm::dvec3& p, const glm::dvec3& n, double dMax,
             double bias) {
  checkAoArguments(n, dMax, bias);
  HB_ASSERT(!views.empty());
  double sum = 0.0;
  for (const LdmView& view : views) {
    const double c = glm::dot(n, view.dir);
    if (c == 0.0) continue;
    uint32_t i, j;
    LdmTrace tr;
    if (ldmProject(view, p, i, j)) tr = ldmTraceList(exactLdmPixel(bvh, view, i, j), ldmDepth(view, p), bias);
    sum += ldmTerm(tr, c, dMax);
  }
  return 2.0 * sum / double(views.size());
}

glm::dvec3 cosineHemisphereDirection(double u, double v, const glm::dvec3& n) {
  constexpr double kQuarterPi = std::numbers::pi / 4.0;
  // Shirley-Chiu concentric map of [-1, 1]² onto the unit disk (area-preserving up to the
  // constant π/4, so uniform strata stay uniform and equal on the disk).
  const double ox = 2.0 * u - 1.0, oy = 2.0 * v - 1.0;
  double dx = 0.0, dy = 0.0;
  if (ox != 0.0 || oy != 0.0) {
    double r, phi;
    if (std::abs(ox) > std::abs(oy))
      r = ox, phi = kQuarterPi * (oy / ox);
    else
      r = oy, phi = 2.0 * kQuarterPi - kQuarterPi * (ox / oy);
    dx = r * std::cos(phi), dy = r * std::sin(phi);
  }
  // Malley: uniform on the disk, lifted to the hemisphere, has density cos θ/π.
  const double dz = std::sqrt(std::max(0.0, 1.0 - dx * dx - dy * dy));
  glm::dvec3 t, b;
  orthonormalBasis(n, t, b);
  return dx * t + dy * b + dz * n;
}

double aoMonteCarlo(const Bvh& bvh, const glm::dvec3& p, const glm::dvec3& n, uint32_t samples, uint64_t seed,
                    double dMax, double tMin) {
  checkAoArguments(n, dMax, tMin);
  const uint32_t k = uint32_t(std::lround(std::sqrt(double(samples))));
  if (samples == 0 || uint64_t(k) * k != samples)
    throw std::invalid_argument("aoMonteCarlo: samples = " + std::to_string(samples) +
                                " is not a positive perfect square (k x k strata)");
  std::mt19937_64 rng(seed);
  const auto uniform = [&rng] { return double(rng() >> 11) * 0x1p-53; };  // [0, 1), portable
  uint32_t visible = 0;
  for (uint32_t sb = 0; sb < k; ++sb)
    for (uint32_t sa = 0; sa < k; ++sa) {
      const double u1 = uniform();
      const double u2 = uniform();
      const glm::dvec3 w = cosineHemisphereDirection((sa + u1) / k, (sb + u2) / k, n);
      visible += !occludedWithin(bvh, p, w, dMax, tMin);
    }
  return double(visible) / double(samples);
}

}  // namespace hb
