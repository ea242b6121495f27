#include "reference/photon_ref.h"
#include "base/numbers.h"

#include <cmath>
#include <numbers>

#include "base/errors.h"
#include "reference/ldm_ref.h"

namespace hb {

namespace {

bool isUnit(const glm::dvec3& v) { return std::abs(glm::length(v) - 1.0) <= 1e-9; }

// Plane coordinate of texel edge i (i = 0..side) or of a texel centre (i = a + 0.5). Edges are
// computed from the integer only, so the edge a texel shares with its neighbour is bit-identical.
double planeCoordinate(const PhotonFace& face, double i) { return face.halfExtent * (2.0 * i / face.side - 1.0); }

glm::dvec3 unnormalisedDirection(const PhotonFace& face, uint32_t a, uint32_t b) {
  HB_ASSERT(a < face.side && b < face.side);
  return face.forward + planeCoordinate(face, a + 0.5) * face.right + planeCoordinate(face, b + 0.5) * face.up;
}

// Solid angle of the plane rectangle [0, x]×[0, y] at unit distance, signed (odd in x and y).
double cornerSolidAngle(double x, double y) { return std::atan2(x * y, std::sqrt(x * x + y * y + 1.0)); }

}  // namespace

std::vector<PhotonFace> cubeFaces(uint32_t side) {
  HB_ASSERT(side >= 1);
  std::vector<PhotonFace> faces;
  for (int k = 0; k < 3; ++k)
    for (double sign : {1.0, -1.0}) {
      glm::dvec3 f(0.0), r(0.0), u(0.0);
      f[k] = sign;
      r[(k + 1) % 3] = sign;
      u[(k + 2) % 3] = 1.0;
      faces.push_back({f, r, u, 1.0, side});
    }
  return faces;
}

PhotonFace spotFace(const glm::dvec3& dir, double cosOuter, uint32_t side) {
  HB_ASSERT(isUnit(dir));
  HB_ASSERT(cosOuter > 0.0 && cosOuter < 1.0);
  HB_ASSERT(side >= 1);
  PhotonFace face{dir, {}, {}, std::sqrt((1.0 - cosOuter) * (1.0 + cosOuter)) / cosOuter, side};
  orthonormalBasis(dir, face.right, face.up);
  return face;
}

glm::dvec3 texelDirection(const PhotonFace& face, uint32_t a, uint32_t b) {
  return glm::normalize(unnormalisedDirection(face, a, b));
}

void texelDirectionDifferentials(const PhotonFace& face, uint32_t a, uint32_t b, glm::dvec3& dDu, glm::dvec3& dDv) {
  const glm::dvec3 D = unnormalisedDirection(face, a, b);
  const double len = glm::length(D);
  const glm::dvec3 d0 = D / len;
  const double step = 2.0 * face.halfExtent / face.side;  // plane distance between texel centres
  // d(D/|D|) = (dD - d0 (d0·dD))/|D|: the part of dD across d0, scaled by 1/|D|.
  const glm::dvec3 du = step * face.right, dv = step * face.up;
  dDu = (du - d0 * glm::dot(d0, du)) / len;
  dDv = (dv - d0 * glm::dot(d0, dv)) / len;
}

double texelSolidAngle(const PhotonFace& face, uint32_t a, uint32_t b) {
  HB_ASSERT(a < face.side && b < face.side);
  const double x0 = planeCoordinate(face, a), x1 = planeCoordinate(face, a + 1.0);
  const double y0 = planeCoordinate(face, b), y1 = planeCoordinate(face, b + 1.0);
  return (cornerSolidAngle(x1, y1) - cornerSolidAngle(x0, y1)) - (cornerSolidAngle(x1, y0) - cornerSolidAngle(x0, y0));
}

void transferDifferential(const glm::dvec3& d, double t, const glm::dvec3& n, glm::dvec3& dx, const glm::dvec3& dd) {
  const double dn = glm::dot(d, n);
  HB_ASSERT(dn != 0.0);
  // The offset ray (x + ε dx) + τ (d + ε dd) meets the plane n·(p - x - t d) = 0 at
  // τ = t + ε dt + O(ε²); its hit moves by ε(dx + t dd + dt d): the plane condition fixes dt.
  const glm::dvec3 moved = dx + t * dd;
  const double dt = -glm::dot(moved, n) / dn;
  dx = moved + dt * d;
}

glm::dvec4 rotationBetween(const glm::dvec3& a, const glm::dvec3& b) {
  HB_ASSERT(isUnit(a) && isUnit(b));
  const double cosTheta = glm::dot(a, b);
  // c = a × b, from the small difference or sum, which is exact where it cancels (Sterbenz):
  // a × a = 0 exactly, and the products are then of the size of the result, not of 1.
  const glm::dvec3 c = cosTheta >= 0.0 ? glm::cross(a, b - a) : glm::cross(a, a + b);
  const double sin2 = glm::dot(c, c);
  if (cosTheta < 0.0 && sin2 < 1e-200) {
    glm::dvec3 axis, unused;
    orthonormalBasis(a, axis, unused);
    return glm::dvec4(axis, 0.0);  // (sin 90°·axis, cos 90°)
  }
  // 1 + cos θ; near antiparallel as sin²θ/(1 - cos θ), whose terms are accurate there.
  const double w = cosTheta >= 0.0 ? 1.0 + cosTheta : sin2 / (1.0 - cosTheta);
  return glm::dvec4(c, w) / std::sqrt(sin2 + w * w);
}

glm::dvec3 rotate(const glm::dvec4& q, const glm::dvec3& v) {
  const glm::dvec3 u(q);
  const glm::dvec3 uv = glm::cross(u, v);
  return v + 2.0 * q.w * uv + 2.0 * glm::cross(u, uv);
}

// Each of the N LDM directions v_i, used the way into n's hemisphere (s_i = sign(n·v_i)), stands
// for itself and -v_i: 2N equal regions of the sphere, so the one used covers Δω = 4π/2N = 2π/N.
// A Lambertian surface of albedo ρ hit by flux Φ over area A reflects radiance L = ρΦ/(πA); the
// flux leaving through Δω about ω is L cos θ A Δω = ρΦ cos θ Δω/π = ρΦ·2|n·v_i|/N. Over the
// hemisphere the weights sum to ρ·(2/N)Σ|n·v_i|, the open-sky quadrature of (1/π)∫ cos θ dω = 1
// (eq_partition_test.cpp: within 1.2 % at N = 64, 0.3 % at N = 256): flux is conserved to that.
double splitWeight(double albedo, double cosTheta, uint32_t N) {
  HB_ASSERT(N >= 1);
  return 2.0 * albedo * std::abs(cosTheta) / double(N);
}

double silvermanKernel(double l) {
  if (!(l < 1.0)) return 0.0;
  const double m = 1.0 - l * l;
  return 3.0 / kPi * m * m;
}

// Why the splat's integral over the photon's plane is Φ: write y - x = α du + β dv (du, dv ⊥ n).
// With den = du·(dv × n) = n·(du × dv) = (n × du)·dv (cyclic triple products) and
// (dv × n)·dv = (n × du)·du = 0, M_p(y - x) = 2/den·(α den, β den, 0) = 2(α, β, 0), so l =
// 2√(α² + β²): the kernel's disk is the ellipse α² + β² < 1/4, inscribed in the parallelogram
// |α|, |β| <= 1/2. dA = |du × dv| dα dβ = A_r dα dβ and, with (α', β') = 2(α, β),
//   ∫ E_p π K dA = (Φ/((π/4) A_r))·π·A_r·∫_disk K dα' dβ'/4 = Φ·∫_disk K = Φ,
// since ∫_disk K = ∫_0^1 (3/π)(1 - l²)² 2πl dl = 1. Off the plane, y - x = h n gives
// M_p(y - x) = (0, 0, 2a h/den), l = 2|h|/√|den|: l = 1 at |h| = ½√|den|.
double splatIrradiance(const glm::dvec3& x, const glm::dvec3& du, const glm::dvec3& dv, const glm::dvec3& n, double phi,
                       const glm::dvec3& y) {
  const double footprint = glm::length(glm::cross(du, dv));  // A_r
  const glm::dvec3 dvXn = glm::cross(dv, n), nXdu = glm::cross(n, du);
  const double den = glm::dot(du, dvXn);
  HB_ASSERT(footprint > 0.0 && den != 0.0);
  const double a = std::sqrt(std::abs(den));
  const glm::dvec3 r = y - x;
  const glm::dvec3 filter = (2.0 / den) * glm::dvec3(glm::dot(dvXn, r), glm::dot(nXdu, r), a * glm::dot(n, r));
  const double irradiance = phi / (0.25 * kPi * footprint);  // E_p
  return irradiance * kPi * silvermanKernel(glm::length(filter));
}

}  // namespace hb
