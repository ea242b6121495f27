// CPU references for single-bounce indirect light by photon differentials, in double precision
// (Aalund, Frisvad, Bærentzen 2015, "Interactive Global Illumination Effects Using
// Deterministically Directed Layered Depth Maps", Sections 3.4 and 4.2; Igehy 1999, "Tracing Ray
// Differentials"; Frisvad, Schjøth, Erleben, Sporring 2014, "Photon Differential Splatting for
// Rendering Caustics"). The GPU shaders use exactly the definitions written here. One photon:
//  emit   d0 = texelDirection, dd = texelDirectionDifferentials, dx = 0 at the light;
//  hit    x1 = light + t d0: transferDifferential(d0, t, n1, dx, dd) for each of u, v;
//  split  per LDM direction d2 (either way): dd2 = rotate(rotationBetween(d0, d2), dd),
//         transferDifferential(d2, t2, n2, dx, dd2), flux Φ·splitWeight(ρ1, n1·d2, N);
//  splat  splatIrradiance at the receivers near x2.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace hb {

// A face of primary photons: side×side texels on the plane at unit distance along `forward`,
// covering plane coordinates [-halfExtent, halfExtent]² (right × up = forward, all unit).
// Texel (a, b), a to the right, b up, index b·side + a, spans s in [e(a), e(a + 1)],
// t in [e(b), e(b + 1)] with the edge e(i) = halfExtent·(2i/side - 1); its centre is
// s = halfExtent·(2(a + 0.5)/side - 1), t likewise; D = forward + s·right + t·up, d0 = D/|D|.
struct PhotonFace {
  glm::dvec3 forward, right, up;
  double halfExtent;
  uint32_t side;
};
// A point light's 6 faces, halfExtent 1, in the order +X, -X, +Y, -Y, +Z, -Z: for axis k and
// sign σ, forward = σ·e_k, right = σ·e_(k+1 mod 3), up = e_(k+2 mod 3) (+X: right +Y, up +Z;
// -Z: right -X, up +Y). Together they cover the sphere once. Precondition: side >= 1.
std::vector<PhotonFace> cubeFaces(uint32_t side);
// A spot light's face: forward = dir, (right, up) = orthonormalBasis(dir), halfExtent =
// tan(acos cosOuter) = √((1 - c)(1 + c))/c. The square holds the cone; texels whose d0·dir <
// cosOuter lie outside it and are the caller's to drop. Preconditions: |dir| = 1 within 1e-9,
// 0 < cosOuter < 1, side >= 1.
PhotonFace spotFace(const glm::dvec3& dir, double cosOuter, uint32_t side);
// d0 of texel (a, b). Precondition (here and below): a, b < side.
glm::dvec3 texelDirection(const PhotonFace& face, uint32_t a, uint32_t b);
// ∂d0/∂a and ∂d0/∂b (per texel): with dD/da = (2·halfExtent/side)·right,
// dd/da = (dD/da - d0 (d0·dD/da))/|D| (the derivative of D/|D|); likewise along up for b.
void texelDirectionDifferentials(const PhotonFace& face, uint32_t a, uint32_t b, glm::dvec3& dDu, glm::dvec3& dDv);
// The texel's exact solid angle: the rectangle [0, x]×[0, y] of the plane subtends
// F(x, y) = atan2(x·y, √(x² + y² + 1)) (signed), so [x0, x1]×[y0, y1] subtends
// F(x1, y1) - F(x0, y1) - F(x1, y0) + F(x0, y0). Adjacent texels evaluate F at bit-identical
// edges, so a face's sum telescopes to its corners up to the rounding of the combinations.
// A texel's photon carries the light's intensity times this (Φ_light·Ω/4π for an isotropic point).
double texelSolidAngle(const PhotonFace& face, uint32_t a, uint32_t b);

// Igehy's transfer of a ray differential (dx, dd) of the ray x + τ·d to its hit x + t·d on a
// surface of normal n (d need not be unit; t is then the ray parameter, not the distance):
//   dx' = dx + t·dd,  dt = -(dx'·n)/(d·n),  dx = dx' + dt·d   (so dx·n = 0: dx lies in the plane).
// dd is unchanged by the transfer (no refraction). Precondition: d·n != 0.
void transferDifferential(const glm::dvec3& d, double t, const glm::dvec3& n, glm::dvec3& dx, const glm::dvec3& dd);

// The unit quaternion (x, y, z, w = scalar) turning unit a into unit b about a × b (the paper's
// α(ω_i, ω_o)): q ∝ (c, w) with c = a × b and w = 1 + a·b, which is 2cos(θ/2)·(sin(θ/2)·u,
// cos(θ/2)). Both are evaluated without cancellation: c as a × (b - a) for a·b >= 0 and
// a × (a + b) otherwise (b ∓ a is exact by Sterbenz where it is small), and, for a·b < 0,
// w = |c|²/(1 - a·b) (= sin²θ/(1 - cos θ)), so that rotate(q, a) = b to ~1e-15 however close to
// antiparallel (1 + a·b keeps only ~1e-16/(1 + a·b) of its digits: 1e-12 from antiparallel,
// b would be missed by ~1e-10). Where |c|² < 1e-200 (b = -a within 1e-100) it is the 180° turn
// about orthonormalBasis(a)'s first vector, which takes a to -a.
// Preconditions: |a| = |b| = 1 within 1e-9.
glm::dvec4 rotationBetween(const glm::dvec3& a, const glm::dvec3& b);
// q v q̄ for unit q = (u, w): v + 2w(u × v) + 2u × (u × v).
glm::dvec3 rotate(const glm::dvec4& q, const glm::dvec3& v);

// The flux fraction of one split photon, 2·albedo·|cosTheta|/N, cosTheta = n·v_i (photon_ref.cpp
// derives it). Summed over the N LDM directions it is albedo·(2/N)Σ|n·v_i| ≈ albedo.
// Precondition: N >= 1.
double splitWeight(double albedo, double cosTheta, uint32_t N);

// Silverman's second-order kernel on the unit disk: (3/π)(1 - l²)² for l < 1, else 0 (∫ = 1).
double silvermanKernel(double l);
// The irradiance a photon at x (flux phi, differentials du, dv in the plane of unit normal n, as
// transferDifferential leaves them; du × dv != 0) adds at receiver y: E_p·π·K(|M_p(y - x)|) with
// A_p = (π/4)|du × dv|, E_p = phi/A_p and M_p = 2/(du·(dv × n))·[dv × n; n × du; a·n],
// a = √|du·(dv × n)|. On the photon's plane its integral is phi (photon_ref.cpp derives it); the
// support is the ellipse inscribed in the parallelogram x ± du/2 ± dv/2. A receiver at normal
// distance h from the plane reaches the kernel's edge at h = ½√|du·(dv × n)| (half the width of
// a square of the footprint's area): a sets how far across a crease a photon still lights.
double splatIrradiance(const glm::dvec3& x, const glm::dvec3& du, const glm::dvec3& dv, const glm::dvec3& n, double phi,
                       const glm::dvec3& y);

}  // namespace hb
