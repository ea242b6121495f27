#include "reference/photon_ref.h"
#include "base/numbers.h"
#include "reference/random_unit.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "reference/eq_partition.h"
#include "reference/ldm_ref.h"

namespace hb {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon() / 2;  // unit roundoff, 2^-53

double faceSolidAngle(const PhotonFace& face) {
  double sum = 0.0;
  for (uint32_t b = 0; b < face.side; ++b)
    for (uint32_t a = 0; a < face.side; ++a) sum += texelSolidAngle(face, a, b);
  return sum;
}

// A face's texel sum telescopes to its corners (adjacent texels share bit-identical edges), so
// only rounding remains. In a texel's (F11 - F01) - (F10 - F00) the inner differences are of
// neighbouring edges, within a factor 2 of each other (exact by Sterbenz) except beside the
// centre lines, where the values are ~h/side; the outer one rounds by <= ε·Ω_texel (ε = 2^-53).
// Adding side² positive terms rounds by <= side²·ε·Ω_face (recursive summation). In all
// <= (side² + a few)·ε relative: 4.6e-13 for side 64, so 1e-12 relative holds with a margin of 2.
TEST(PhotonRef, CubeFaceTexelSolidAnglesSumToFourPi) {
  for (uint32_t side : {1u, 7u, 64u}) {
    const auto faces = cubeFaces(side);
    ASSERT_EQ(faces.size(), 6u);
    double total = 0.0;
    for (const PhotonFace& f : faces) {
      EXPECT_EQ(glm::cross(f.right, f.up), f.forward);  // axis vectors: exact
      total += faceSolidAngle(f);
    }
    EXPECT_NEAR(total, 4.0 * kPi, 1e-12 * 4.0 * kPi) << "side " << side;
  }
}

TEST(PhotonRef, SpotFaceTexelSolidAnglesSumToTheSquarePyramid) {
  // A square of half-side h at unit distance subtends 4·atan(h²/√(1 + 2h²)) = 4·asin(h²/(1 + h²)).
  // Rounding as above; asin's slope 1/√(1 - x²) <= 5 for cones up to 80° (x = h²/(1 + h²)).
  // halfExtent = √((1 - c)(1 + c))/c: 1 - c is exact, but c's own rounding is amplified by
  // c/(1 - c) <= 66 at 10° (and halved by √): ~35ε = 4e-15 relative, within 1e-14.
  std::mt19937_64 rng(7);
  for (double degrees : {10.0, 30.0, 60.0, 80.0})
    for (uint32_t side : {1u, 7u, 64u}) {
      const PhotonFace f = spotFace(randomUnit(rng), std::cos(degrees * kPi / 180.0), side);
      const double h = f.halfExtent;
      EXPECT_NEAR(h, std::tan(degrees * kPi / 180.0), 1e-14 * h);
      const double pyramid = 4.0 * std::asin(h * h / (1.0 + h * h));
      EXPECT_NEAR(faceSolidAngle(f), pyramid, 1e-12 * pyramid) << degrees << "° side " << side;
    }
}

// d0 at fractional texel coordinates, from the definition in photon_ref.h.
glm::dvec3 directionAt(const PhotonFace& f, double a, double b) {
  const double s = f.halfExtent * (2.0 * (a + 0.5) / f.side - 1.0), t = f.halfExtent * (2.0 * (b + 0.5) / f.side - 1.0);
  return glm::normalize(f.forward + s * f.right + t * f.up);
}

TEST(PhotonRef, TexelDirectionDifferentialsAreTheDerivativesOfTheDirection) {
  // d0(a) = D/|D| moves on a great circle, D running along a line at distance ρ >= 1 from the
  // light (forward ⊥ right, up) at k = 2h/side per texel. On the circle, with u the line
  // parameter, |d'''(u)| = 3√(4u⁴ + ρ⁴)ρ/(ρ² + u²)³ <= 3/ρ³, so the central difference with step e
  // is off by <= e²/6 · 3k³ = e²k³/2. e = 2^-10 makes a ± e exact; each direction carries
  // <= (4 + 4h) roundings of 1 (normalize, and the plane coordinates' ulps of h), so the
  // quotient's rounding is <= 2(4 + 4h)ε/(2e).
  const double e = 1.0 / 1024;
  std::vector<PhotonFace> faces = cubeFaces(1);
  for (uint32_t side : {7u, 64u}) faces.push_back(cubeFaces(side)[3]);
  std::mt19937_64 rng(3);
  for (uint32_t side : {1u, 5u, 64u}) faces.push_back(spotFace(randomUnit(rng), std::cos(80.0 * kPi / 180.0), side));
  for (const PhotonFace& f : faces) {
    const double k = 2.0 * f.halfExtent / f.side;
    const double tol = e * e * k * k * k / 2.0 + (4.0 + 4.0 * f.halfExtent) * kEps / e;
    for (uint32_t b = 0; b < f.side; b += 1 + f.side / 8)
      for (uint32_t a = 0; a < f.side; a += 1 + f.side / 8) {
        glm::dvec3 dDu, dDv;
        texelDirectionDifferentials(f, a, b, dDu, dDv);
        EXPECT_EQ(texelDirection(f, a, b), directionAt(f, a, b));
        const glm::dvec3 fu = (directionAt(f, a + e, b) - directionAt(f, a - e, b)) / (2.0 * e);
        const glm::dvec3 fv = (directionAt(f, a, b + e) - directionAt(f, a, b - e)) / (2.0 * e);
        EXPECT_LE(glm::length(dDu - fu), tol) << "side " << f.side << " texel " << a << "," << b;
        EXPECT_LE(glm::length(dDv - fv), tol) << "side " << f.side << " texel " << a << "," << b;
      }
  }
}

TEST(PhotonRef, TransferMatchesTheHitsOfOffsetRays) {
  // The offset ray (x0 + ε dx) + τ(d + ε dd) meets the plane n·(p - x0 - t d) = 0 at
  // τ(ε) = t - ε(h + t g)/(c + ε g), with c = n·d, g = n·dd, h = n·dx. Its hit minus x0 + t d,
  // over ε, differs from Igehy's dx by exactly ε(h + t g)/(c + ε g)·((g/c) d - dd): the bound
  // below. Rounding: hit points of size X carry <= 8εX, the quotient 16εX/ε.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  const double eps = 1e-6;
  for (int k = 0; k < 200; ++k) {
    const glm::dvec3 x0(3 * uni(rng), 3 * uni(rng), 3 * uni(rng));
    const glm::dvec3 d = randomUnit(rng) * (k % 2 ? 1.0 : 1.7);    // unit and not
    glm::dvec3 n = k == 0 ? -glm::normalize(d) : randomUnit(rng);  // head-on, else tilted
    if (std::abs(glm::dot(n, glm::normalize(d))) < 0.2) continue;  // grazing: the bound grows as 1/c
    const double t = 0.5 + 4.5 * (uni(rng) + 1.0) / 2.0;
    const glm::dvec3 dx0(uni(rng), uni(rng), uni(rng)), dd(uni(rng), uni(rng), uni(rng));
    const glm::dvec3 p1 = x0 + t * d;
    auto hit = [&](double s) {
      const glm::dvec3 o = x0 + s * dx0, w = d + s * dd;
      return o + (glm::dot(n, p1 - o) / glm::dot(n, w)) * w;
    };
    glm::dvec3 dx = dx0;
    transferDifferential(d, t, n, dx, dd);
    const double c = glm::dot(n, d), g = glm::dot(n, dd), h = glm::dot(n, dx0);
    const double X = glm::length(x0) + t * glm::length(d) + glm::length(dx0) + glm::length(dd);
    const double bound =
        eps * std::abs(h + t * g) / std::abs(c + eps * g) * (std::abs(g / c) * glm::length(d) + glm::length(dd));
    EXPECT_LE(glm::length((hit(eps) - hit(0.0)) / eps - dx), bound + 16.0 * kEps * X / eps) << k;
    // dx lies in the plane: dx·n = 0 up to the rounding of dx' + dt d (terms <= |dx'| + |dt d|).
    const glm::dvec3 moved = dx0 + t * dd;
    EXPECT_LE(std::abs(glm::dot(dx, n)), 8.0 * kEps * (glm::length(moved) + glm::length(dx - moved))) << k;
  }
}

// q's terms cancel only where Sterbenz makes them exact, so q carries a few ulps, and rotate
// (about 12 operations on values <= 3) adds ~20 ulps of 3: ~1e-14. 1e-12 leaves a margin of 100.
TEST(PhotonRef, RotationBetweenTurnsAIntoB) {
  std::mt19937_64 rng(5);
  for (int k = 0; k < 500; ++k) {
    const glm::dvec3 a = randomUnit(rng), w = randomUnit(rng);
    const double delta = std::pow(10.0, -(k % 16));  // 1 .. 1e-15
    for (const glm::dvec3& b : {w, glm::normalize(-a + delta * w), glm::normalize(a + delta * w), a, -a}) {
      const glm::dvec4 q = rotationBetween(a, b);
      EXPECT_NEAR(glm::length(q), 1.0, 1e-15);
      EXPECT_LE(glm::length(rotate(q, a) - b), 1e-12) << "a·b = " << glm::dot(a, b) << " delta " << delta;
    }
  }
}

TEST(PhotonRef, RotationPreservesLengthsAndAngles) {
  // A unit q (within 1e-15) makes rotate orthogonal to ~1e-15; products of values <= 3 keep
  // |v|² and v·w within ~30 ulps of 9: 1e-13.
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  for (int k = 0; k < 500; ++k) {
    const glm::dvec3 a = randomUnit(rng);
    const glm::dvec3 b = k % 3 ? randomUnit(rng) : glm::normalize(-a + 1e-7 * randomUnit(rng));
    const glm::dvec4 q = rotationBetween(a, b);
    const glm::dvec3 v(uni(rng), uni(rng), uni(rng)), w(uni(rng), uni(rng), uni(rng));
    EXPECT_NEAR(glm::dot(rotate(q, v), rotate(q, v)), glm::dot(v, v), 1e-13);
    EXPECT_NEAR(glm::dot(rotate(q, v), rotate(q, w)), glm::dot(v, w), 1e-13);
    // A directional differential across d1 stays across d2 = rotate(q, d1) (the split's dd2):
    // rotate(q, dd)·b = dd·a + rotate(q, dd)·(b - rotate(q, a)), <= 1e-15 + 1e-14 per |dd|.
    const glm::dvec3 dd = v - a * glm::dot(a, v);
    EXPECT_LE(std::abs(glm::dot(rotate(q, dd), b)), 1e-13 * glm::length(dd));
  }
}

TEST(PhotonRef, SplitWeightsOverTheLdmDirectionsSumToTheAlbedo) {
  // Σ_i splitWeight = albedo·(2/N)Σ|n·v_i|: the open-sky quadrature, within the bounds that
  // eq_partition_test.cpp holds for random normals (1.2 % at N = 64, 0.3 % at N = 256). Same
  // generator and seed as there: these normals are among those it checks at N = 64.
  std::mt19937_64 rng(16);
  std::vector<glm::dvec3> normals;
  for (int k = 0; k < 5; ++k) normals.push_back(randomUnit(rng));
  for (const auto& [n, bound] : {std::pair{64u, 0.012}, std::pair{256u, 0.003}}) {
    const auto dirs = ldmDirections(n);
    for (const glm::dvec3& m : normals)
      for (double albedo : {0.2, 0.8}) {
        double sum = 0.0;
        for (const glm::dvec3& v : dirs) sum += splitWeight(albedo, glm::dot(m, v), n);
        EXPECT_NEAR(sum, albedo, bound * albedo) << "N = " << n;
      }
  }
}

struct SplatCase {
  glm::dvec3 x, n, e1, e2, du, dv;
};

SplatCase splatCase(std::mt19937_64& rng, glm::dvec2 du, glm::dvec2 dv) {
  SplatCase c;
  c.x = glm::dvec3(0.3, -1.2, 2.0);
  c.n = randomUnit(rng);
  orthonormalBasis(c.n, c.e1, c.e2);
  c.du = du.x * c.e1 + du.y * c.e2;
  c.dv = dv.x * c.e1 + dv.y * c.e2;
  return c;
}

TEST(PhotonRef, SplatIntegratesToTheFluxOverThePhotonsPlane) {
  // Midpoint rule on an M×M grid over the parallelogram y = x + α du + β dv, |α|, |β| <= 1/2,
  // which holds the ellipse; a cell of side s = 1/M has area A_r s², A_r = |du × dv| taken from
  // the 2D coordinates. Per unit αβ the integrand is g = A_r E_p π K(2|(α, β)|) = 4Φ K(2r),
  // whose gradient is Lipschitz (K and K' vanish at l = 1) with |Hessian| <= 4Φ·4·|H_K| and
  // |H_K| = |(3/π)(8 p pᵀ - 4(1 - r²) I)| <= 24/π. Per cell the error is <= |H| s⁴/12 (Taylor
  // about the centre; ∫(δα² + δβ²) = s⁴/6), over the unit square <= |H| s²/12 = (32/π)Φ s²;
  // summing M² terms adds <= M²εΦ. In (α, β) the integrand does not depend on du, dv (that is
  // what M_p is for): the cases agree to rounding.
  std::mt19937_64 rng(21);
  const double phi = 2.5;
  const int m = 1000;
  const double s = 1.0 / m;
  for (const auto& [du2, dv2] : {std::pair{glm::dvec2(1.0, 0.2), glm::dvec2(0.5, 0.6)},
                                 std::pair{glm::dvec2(0.5, 0.6), glm::dvec2(1.0, 0.2)},  // du·(dv×n) < 0
                                 std::pair{glm::dvec2(0.1, 0.0), glm::dvec2(-0.7, 0.9)}}) {
    const SplatCase c = splatCase(rng, du2, dv2);
    double sum = 0.0;
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) {
        const glm::dvec3 y = c.x + (-0.5 + (i + 0.5) * s) * c.du + (-0.5 + (j + 0.5) * s) * c.dv;
        sum += splatIrradiance(c.x, c.du, c.dv, c.n, phi, y);
      }
    sum *= std::abs(du2.x * dv2.y - du2.y * dv2.x) * s * s;
    const double tol = 32.0 / kPi * phi * s * s + double(m) * m * kEps * phi;
    std::printf("[ splat ] integral - flux = %.3e (bound %.3e)\n", sum - phi, tol);
    EXPECT_NEAR(sum, phi, tol);
  }
}

TEST(PhotonRef, SplatVanishesOutsideTheEllipseAndBeyondItsNormalReach) {
  // y = x + (ρ/2)(cos θ du + sin θ dv) has l = ρ (M_p maps it to ρ(cos θ, sin θ, 0)); computed l
  // is ρ within ~10 ulps, so ρ = 1 + 1e-9 gives exactly 0 and ρ = 1 - 1e-6 gives > 0.
  std::mt19937_64 rng(23);
  const double phi = 1.5;
  const SplatCase c = splatCase(rng, {0.8, -0.1}, {0.3, 0.4});
  const double den = glm::dot(c.du, glm::cross(c.dv, c.n));
  const double ep = phi / (kPi / 4 * glm::length(glm::cross(c.du, c.dv)));
  EXPECT_NEAR(splatIrradiance(c.x, c.du, c.dv, c.n, phi, c.x), 3.0 * ep, 1e-14 * ep);  // π K(0) = 3
  for (int k = 0; k < 64; ++k) {
    const double th = 2 * kPi * k / 64;
    const glm::dvec3 dir = 0.5 * (std::cos(th) * c.du + std::sin(th) * c.dv);
    for (double rho : {1.0 + 1e-9, 1.5, 4.0})
      EXPECT_EQ(splatIrradiance(c.x, c.du, c.dv, c.n, phi, c.x + rho * dir), 0.0);
    EXPECT_GT(splatIrradiance(c.x, c.du, c.dv, c.n, phi, c.x + (1.0 - 1e-6) * dir), 0.0);
  }
  // Along the normal l = 2|h|/√|den|: the edge at |h| = ½√|den|, on both sides of the plane.
  const double reach = 0.5 * std::sqrt(std::abs(den));
  for (double side : {1.0, -1.0}) {
    EXPECT_EQ(splatIrradiance(c.x, c.du, c.dv, c.n, phi, c.x + side * reach * (1.0 + 1e-9) * c.n), 0.0);
    // At the edge itself l = 1 within ~10 ulps: K <= (3/π)(2·10ε)² = 4e-29.
    EXPECT_LE(splatIrradiance(c.x, c.du, c.dv, c.n, phi, c.x + side * reach * c.n), ep * kPi * 4e-29);
    EXPECT_GT(splatIrradiance(c.x, c.du, c.dv, c.n, phi, c.x + side * reach * (1.0 - 1e-6) * c.n), 0.0);
  }
}

}  // namespace
}  // namespace hb
