// CPU references for layered depth maps (LDMs) and ambient occlusion (AO), in double precision
// (Aalund, Frisvad, Bærentzen 2015, "Interactive Global Illumination Effects Using
// Deterministically Directed Layered Depth Maps", Sections 3.1-3.3 and 4.1). The GPU side uses
// exactly the definitions written here: basis, pixel mapping, depth, trace and AO sum.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "reference/bvh.h"

namespace hb {

// Branchless orthonormal basis (Duff, Burgess, Christensen, Hill, Kensler, Pharr, "Building an
// Orthonormal Basis, Revisited", JCGT 6(1), 2017), for unit f:
//   s = (f.z >= 0 ? 1 : -1)   (-0.0 counts as +: GLSL has no copysign; both choices are valid)
//   a = -1/(s + f.z), b = f.x f.y a
//   b1 = (1 + s f.x² a, s b, -s f.x),  b2 = (b, s + f.y² a, -f.y)
// b1, b2, f are orthonormal and right-handed (b1 × b2 = f) to a few ulps for every unit f.
void orthonormalBasis(const glm::dvec3& f, glm::dvec3& b1, glm::dvec3& b2);

// An orthographic LDM looking along `dir` (unit) over the sphere (centre, radius), R×R pixels.
//  right, up = orthonormalBasis(-dir): right × up = -dir (a camera looking along dir, as view
//    space looks down -z); dir = -z gives right = +x, up = +y.
//  Pixel (i, j), i to the right, j down, index j·R + i: its line is parallel to dir through
//    centre + ((2(i + 0.5)/R - 1)·radius)·right + ((1 - 2(j + 0.5)/R)·radius)·up.
//  A point p lies in pixel (floor((u + 1)R/2), floor((1 - v)R/2)) with u = dot(p - centre, right)/radius,
//    v = dot(p - centre, up)/radius; outside the map unless both are in [0, R).
//  Depth z = dot(p - centre, dir) + radius: 0 on the near side of the sphere, 2·radius on the far.
struct LdmView {
  glm::dvec3 dir, right, up, centre;
  double radius;
  uint32_t resolution;
};
// Preconditions (HB_ASSERT): |dir| = 1 within 1e-9, radius > 0, resolution >= 1.
LdmView ldmView(const glm::dvec3& dir, const glm::dvec3& centre, double radius, uint32_t resolution);
// The point of pixel (i, j)'s line at depth 0. Precondition: i, j < resolution.
glm::dvec3 ldmPixelOrigin(const LdmView& view, uint32_t i, uint32_t j);
// The pixel p lies in; false when p is outside the map.
bool ldmProject(const LdmView& view, const glm::dvec3& p, uint32_t& i, uint32_t& j);
double ldmDepth(const LdmView& view, const glm::dvec3& p);

// A bounding sphere for LDM views of everything in `bvh`: the centre of the triangles' AABB and
// half its diagonal times (1 + 1e-6), so that every vertex lies strictly inside the depth range
// [0, 2·radius] and the map (rounding is ~1e-16 relative). An empty bvh gives radius 1.
struct LdmSphere {
  glm::dvec3 centre;
  double radius;
};
LdmSphere ldmBoundingSphere(const Bvh& bvh);

// The exact counterpart of a GPU-built LDM: per pixel every depth z in [0, 2·radius] where the
// pixel's line meets a triangle (both faces), ascending, by ray casting (Bvh::allHits) through
// the pixel centre. Where the line passes exactly through an edge or vertex shared by triangles,
// hits within 1e-9·2·radius of each other count once per facing (sign of dot(geometric normal,
// dir)): a rasterizer's fill rule gives a shared edge between two triangles facing the same way
// to one of them, while a silhouette edge (one front-, one back-facing) gives an in and an out.
// Two distinct surfaces facing the same way closer than that along a line merge too.
// Storage as a GPU prefix-sum layout: pixel k = j·R + i holds depths[first[k] .. first[k + 1]).
struct ExactLdm {
  LdmView view;
  std::vector<uint32_t> first;  // R·R + 1 offsets
  std::vector<double> depths;
  std::span<const double> pixel(uint32_t i, uint32_t j) const;
};
ExactLdm exactLdm(const Bvh& bvh, const LdmView& view);
// The list of one pixel, as exactLdm stores it.
std::vector<double> exactLdmPixel(const Bvh& bvh, const LdmView& view, uint32_t i, uint32_t j);

// Nodes (depths) per pixel over all R·R pixels, empty ones included; p99 is the nearest-rank
// 99th percentile (the smallest count that at least 99 % of pixels do not exceed).
struct LdmNodeStats {
  uint64_t pixels = 0, nodes = 0;
  double mean = 0.0;
  uint32_t p99 = 0, max = 0;
};
LdmNodeStats ldmNodeStats(const ExactLdm& ldm);

// trace(x, ±dir) on one pixel's ascending list (paper 3.1, steps 3-4), both directions from one
// search: with z_x the depth of x,
//   forward  (+dir): the first entry z > z_x + bias, at distance z - z_x;
//   backward (-dir): the last entry z < z_x - bias, at distance z_x - z.
// Entries within bias of z_x (the surface x lies on) are skipped. On the GPU one ascending walk
// does it: remember the last z < z_x - bias, stop at the first z > z_x + bias.
// Precondition: bias >= 0.
struct LdmHit {
  bool hit = false;
  double distance = 0.0;
};
struct LdmTrace {
  LdmHit forward, backward;
};
LdmTrace ldmTraceList(std::span<const double> sorted, double zx, double bias);
// Steps 2-4: x's pixel (none when x is outside the map), z_x = ldmDepth(view, x), then the above.
LdmTrace ldmTrace(const ExactLdm& ldm, const glm::dvec3& x, double bias);

// AO by the paper's eq. 2 with the LDM directions v_i (each standing for v_i and -v_i):
//   AO(p, n) = (2/N) Σ_i V(p, s_i v_i) |n·v_i|,  s_i = sign(n·v_i)  (terms with n·v_i = 0 are 0)
// V = 0 when the first hit along s_i v_i lies within (tMin, dMax], else 1: dMax = +inf is
// ambient occlusion, a finite dMax the obscurance cut. Ray traced with the Bvh (the exact
// counterpart of LDM AO along the same directions). Preconditions: n unit, dirs unit and
// non-empty, 0 <= tMin < dMax.
double aoRayTraced(const Bvh& bvh, const glm::dvec3& p, const glm::dvec3& n, const std::vector<glm::dvec3>& dirs,
                   double dMax, double tMin);
// The same sum with v_i = ldms[i].view.dir and V from ldmTrace(ldms[i], p, bias): 0 when the
// trace in direction s_i (forward for n·v_i > 0) hits at a distance <= dMax. The bias plays
// tMin's part: this equals aoRayTraced(..., tMin = bias) wherever each pixel line meets the
// scene as p's ray does. The pixel line is p's line moved by up to d = √2·radius/R (half a pixel
// diagonal), so a term can differ only where (a) d·tan θ > bias, θ between v and the normal of
// the surface p lies on (that surface's own entry drifts up to d·tan θ from z_x: self-occlusion),
// or (b) p's line passes within d of an outline edge of the occluders (ldm_ref_test.cpp derives
// and tests this). Precondition: 0 <= bias < dMax.
double aoLdm(const std::vector<ExactLdm>& ldms, const glm::dvec3& p, const glm::dvec3& n, double dMax, double bias);
// Bit for bit the same as aoLdm on exactLdm(bvh, views[i]), building only the pixel each trace
// reads (for many directions at high resolution).
double aoLdm(const Bvh& bvh, const std::vector<LdmView>& views, const glm::dvec3& p, const glm::dvec3& n, double dMax,
             double bias);

// The sample direction for (u, v) in [0, 1]²: Shirley-Chiu's concentric map to the unit disk
// (area-preserving up to a constant), Malley's lift to the hemisphere about n
// (z = √(1 - x² - y²): density cos θ/π), in the frame (b1, b2, n) = orthonormalBasis(n).
glm::dvec3 cosineHemisphereDirection(double u, double v, const glm::dvec3& n);

// The converged reference: cosine-weighted, stratified Monte Carlo, AO = (1/S) Σ V with V as in
// aoRayTraced. samples = S = k² strata of the unit square (std::invalid_argument naming samples
// otherwise); stratum (a, b), b outer, a inner, takes cosineHemisphereDirection((a + ξ1)/k,
// (b + ξ2)/k, n) with ξ1 then ξ2 drawn from std::mt19937_64(seed) as (x >> 11)·2^-53 (portable,
// unlike std::uniform_real_distribution). Error: only strata the visibility outline crosses err,
// by at most 1/S each; standard deviation <= √K/(2S) for K such strata.
double aoMonteCarlo(const Bvh& bvh, const glm::dvec3& p, const glm::dvec3& n, uint32_t samples, uint64_t seed,
                    double dMax, double tMin);

}  // namespace hb
