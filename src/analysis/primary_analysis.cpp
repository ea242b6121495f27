#include "analysis/primary_analysis.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>

#include "base/errors.h"
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

Raster3dView raster3dViewOf(const gpu::Raster3dConstants& c) {
  Raster3dView view;
  view.eye = glm::vec3(c.eye);
  view.d0 = glm::vec3(c.rayD0);
  view.dx = glm::vec3(c.rayDx);
  view.dy = glm::vec3(c.rayDy);
  view.width = c.width;
  view.height = c.height;
  view.znear = c.depth.x;
  view.zfar = c.depth.y;
  return view;
}

CoverageComparison compareCoverage(const Scene& scene, const gpu::Raster3dConstants& c,
                                   const std::vector<uint32_t>& method, const std::vector<uint8_t>* band) {
  const std::vector<glm::vec3> positions = scene.worldTriangles();
  std::vector<uint32_t> indices(positions.size());
  for (size_t i = 0; i < indices.size(); ++i) indices[i] = uint32_t(i);
  const Raster3dResult exact = rasterize3d(raster3dViewOf(c), positions, indices);
  HB_ASSERT(!band || band->size() == exact.coverage.size());
  CoverageComparison r;
  for (size_t i = 0; i < exact.coverage.size() && i < method.size(); ++i) {
    ++r.pixels;
    r.coveredPixels += exact.coverage[i] > 0;
    r.doubleCovers += method[i] > exact.coverage[i];
    r.holes += method[i] < exact.coverage[i];
    if (!band) continue;
    r.bandPixels += (*band)[i] != 0;
    r.outsideBand += method[i] != exact.coverage[i] && (*band)[i] == 0;
  }
  return r;
}

// The rounding band of 2D homogeneous rasterization (raster3d.glsl.inc r2dSetup, r3dCovers).
//
// The exact decision. Let D = [dx dy d0] (the float ray constants as exact numbers, columns), so
// that d(x, y) = D·(x, y, 1), and v = D⁻¹p for each eye-relative float vertex p (r3dRelative rounds
// as C++ float does): p = W·d(X/W, Y/W), so v = (X, Y, W) are p's homogeneous pixel coordinates in
// exactly the rays the 3D reference tests. For edge (a, b), E(x, y) = (v_a × v_b)·(x, y, 1) =
// det(D⁻¹)·(p_a × p_b)·d(x, y), and the triangle's det = v_0·(v_1 × v_2) = det(D⁻¹)·det[p_0 p_1 p_2],
// so E_i/det = V_i/V, the 3D edge function over the volume (raster3d.glsl.inc): the oriented 2DH
// test on v decides exactly what the exact 3D rasterization decides.
//
// What the shader computes instead (u = 2^-24):
//  - v_f = r2dVertex(p) = M_f·p + r, M_f the matrix of r2dVertex's float constants (forward, right,
//    up, project) and r its float rounding: W a dot product of three terms (γ3 of Σ|p_j f_j|), X and
//    Y two more products and a sum (γ5 of |project.x|·Σ|p_j r_j| + |project.z|·Σ|p_j f_j|); γ5 < 6u.
//  - M_f is D⁻¹ but for the rounding of the constants: M_f·D = I + Δ. A common linear map does not
//    matter the way per-vertex errors do: (Av_a × Av_b)·k = det(A)·(v_a × v_b)·A⁻¹k, so with
//    A = I + Δ (det > 0) every edge sees the exact vertices at the pixel moved to k' = A⁻¹k,
//    normalised (x', y', 1) (δ = (x' − x, y' − y), a few u of the pixel coordinates), and the
//    orientation keeps its sign. What is left is w = v + A⁻¹r per vertex.
//  - A vertex scaled by a positive factor changes no sign, so only r's part across v counts:
//    r = σ·v + τ with σ = r_W/W (|r_W| < |W|) leaves τ = (r_X − x·r_W, r_Y − y·r_W, 0) (x = X/W),
//    |τ_X| <= |r_X| + |x|·|r_W|: the vertex moved in the image, W times its pixel displacement.
//    With τ's zero third component, exactly:
//      (τ_a × v_b + v_a × τ_b + τ_a × τ_b)·(x, y, 1) = τ_aX(Y_b − y·W_b) + τ_aY(x·W_b − X_b)
//                                                     − τ_bX(Y_a − y·W_a) − τ_bY(x·W_a − X_a) + τ_aXτ_bY − τ_aYτ_bX,
//    W_b times the lever arm of the pixel about the other end; likewise det moves by at most
//    Σ_k (|τ_kX|·|e_kx| + |τ_kY|·|e_ky|) + Σ |W_m|(|τ_iX||τ_jY| + |τ_iY||τ_jX|) (e_k the edge rows).
//  - The float evaluation: each cross product component two products and a difference (<= 2u of
//    its terms' magnitudes, M = |v_fa| ×ₘ |v_fb|, ×ₘ the cross product of magnitudes), then
//    E = (A + x·B) + y·C two products and two sums (<= 3u of |A| + x|B| + y|C|): 6u·M·(x, y, 1) in
//    all (5u and its second-order terms); det = v_f0·(v_f1 × v_f2) likewise, 6u·|v_f0|·(|v_f1| ×ₘ |v_f2|).
//    This term is the large one: the constant row A is a difference of products of pixel
//    coordinates, so its rounding is u·x·y·W², a thousandth of a pixel for 1-px edges at 160x90.
// Everything here is evaluated in double: D⁻¹, the products and the cancellations err by a few
// u_d·cond(D), which the slack 32·u_d·‖D‖₁‖D⁻¹‖₁ of each magnitude covers.
//
// So an edge whose |E| exceeds that bound has the float value's sign, and a triangle with one edge
// certainly negative, or all three certainly positive, is decided as exactly. The rest are
// uncertain, and their count may still be right: the two triangles of a shared edge compute the
// same v_f for its endpoints (the same float p, the same operations under `precise`) and cross them
// in opposite order, so their rows are exact negations (a·b − c·d against c·d − a·b, rounded alike),
// and so are their pixel values: a centre near that edge alone goes to exactly one of the two,
// as in exact arithmetic. A pixel is in the band when a triangle has two or more uncertain edges
// there (a vertex), when its uncertain edges are not exactly one such negated pair (an edge not
// shared, or two different edges: three triangles around a vertex), when a triangle's orientation
// is uncertain (a sliver: either sign may come out, so the pixel is out for both only where one edge
// is certainly positive and another certainly negative), when a vertex lies within rounding of the
// eye plane (W ~ 0: the whole box), or when a triangle it may be in is hit nearer than znear (the
// two methods' screen boxes, each the part in front of znear/2 plus a pixel, may then differ).
// Boxes here are the reference's plus 2 pixels (the shader's differs by rounding and its own pixel
// of margin).
std::vector<uint8_t> raster2dRoundingBand(const Scene& scene, const gpu::Raster3dConstants& c) {
  HB_ASSERT(c.projection == gpu::kProjectionPerspective);
  constexpr double u = 0x1p-24, ud = 0x1p-53;
  const Raster3dView view = raster3dViewOf(c);
  const glm::dmat3 D(glm::dvec3(c.rayDx), glm::dvec3(c.rayDy), glm::dvec3(c.rayD0));  // columns
  const glm::dmat3 toPixel = glm::inverse(D);
  auto norm1 = [](const glm::dmat3& m) {
    double n = 0.0;
    for (int j = 0; j < 3; ++j) n = std::max(n, std::abs(m[j].x) + std::abs(m[j].y) + std::abs(m[j].z));
    return n;
  };
  const double slack = 32.0 * ud * norm1(D) * norm1(toPixel);
  const glm::dvec3 fwd(c.forward), right(c.right), up(c.up);
  const glm::dvec4 proj(c.project);
  // M_f (rows: X, Y, W as r2dVertex forms them) and A⁻¹ = (M_f·D)⁻¹, which moves a pixel to k'.
  const glm::dmat3 mf = glm::transpose(glm::dmat3(proj.x * right + proj.z * fwd, -proj.y * up + proj.w * fwd, fwd));
  const glm::dmat3 A = mf * D;
  HB_ASSERT(glm::determinant(A) > 0.0);
  const glm::dmat3 aInv = glm::inverse(A);
  glm::dmat3 aInvAbs;  // |A⁻¹| entry by entry: |A⁻¹r| <= |A⁻¹|·|r|
  for (int j = 0; j < 3; ++j) aInvAbs[j] = glm::abs(aInv[j]);
  // |a| ×ₘ |b|: per component the sum of the two products' magnitudes.
  auto crossMag = [](const glm::dvec3& a, const glm::dvec3& b) {
    return glm::dvec3(a.y * b.z + a.z * b.y, a.z * b.x + a.x * b.z, a.x * b.y + a.y * b.x);
  };
  struct BandVertex {
    glm::dvec3 v, absF;  // v = D⁻¹p; a bound on |v_f| (for the float evaluation's magnitudes)
    double tauX, tauY;   // bounds on τ's components
    bool okW;            // |W| exceeds r_W: the split r = σv + τ exists
  };
  auto vertex = [&](const glm::vec3& pf) {
    const glm::dvec3 p(pf), ap = glm::abs(p);
    const double sw = glm::dot(ap, glm::abs(fwd));
    const glm::dvec3 mag(std::abs(proj.x) * glm::dot(ap, glm::abs(right)) + std::abs(proj.z) * sw,
                         std::abs(proj.y) * glm::dot(ap, glm::abs(up)) + std::abs(proj.w) * sw, sw);
    BandVertex r;
    r.v = toPixel * p;
    const glm::dvec3 rb = aInvAbs * (6.0 * u * mag + slack * (glm::abs(r.v) + mag));  // |A⁻¹r|
    r.absF = glm::abs(mf * p) + 6.0 * u * mag + slack * (glm::abs(r.v) + mag);
    r.okW = std::abs(r.v.z) > 2.0 * rb.z;
    const double x = r.okW ? std::abs(r.v.x / r.v.z) : 0.0, y = r.okW ? std::abs(r.v.y / r.v.z) : 0.0;
    r.tauX = rb.x + x * rb.z;
    r.tauY = rb.y + y * rb.z;
    return r;
  };
  // An edge by its endpoints' float bits, smaller first, and which way the triangle runs along it.
  using EdgeKey = std::array<uint32_t, 6>;
  auto bitsOf = [](const glm::vec3& p) {
    return std::array<uint32_t, 3>{std::bit_cast<uint32_t>(p.x), std::bit_cast<uint32_t>(p.y),
                                   std::bit_cast<uint32_t>(p.z)};
  };
  struct EdgeRecord {
    EdgeKey key;
    int side;  // orientation × (+1 if the edge runs from the smaller endpoint): negated rows differ in side
  };
  const size_t pixels = size_t(c.width) * c.height;
  std::vector<uint8_t> band(pixels, 0);
  std::vector<std::vector<EdgeRecord>> records(pixels);
  const std::vector<glm::vec3> world = scene.worldTriangles();
  const glm::vec3 eye(c.eye);
  for (size_t k = 0; k + 2 < world.size(); k += 3) {
    const glm::vec3 p[3] = {world[k] - eye, world[k + 1] - eye, world[k + 2] - eye};  // r3dRelative
    const glm::dvec3 pd[3] = {glm::dvec3(p[0]), glm::dvec3(p[1]), glm::dvec3(p[2])};
    glm::ivec2 lo, hi;
    screenBox3d(view, pd, lo, hi);
    if (hi.x < lo.x || hi.y < lo.y) continue;
    lo = glm::max(lo - 2, glm::ivec2(0));
    hi = glm::min(hi + 2, glm::ivec2(int(c.width) - 1, int(c.height) - 1));
    const BandVertex v[3] = {vertex(p[0]), vertex(p[1]), vertex(p[2])};
    const glm::dvec3 e[3] = {glm::cross(v[1].v, v[2].v), glm::cross(v[2].v, v[0].v), glm::cross(v[0].v, v[1].v)};
    const double det = glm::dot(v[0].v, e[0]);
    double detBound = 6.0 * u * glm::dot(v[0].absF, crossMag(v[1].absF, v[2].absF)) +
                      slack * glm::dot(glm::abs(v[0].v), crossMag(glm::abs(v[1].v), glm::abs(v[2].v)));
    for (int i = 0; i < 3; ++i) {
      const BandVertex &a = v[i], &b = v[(i + 1) % 3], &m = v[(i + 2) % 3];
      detBound +=
          a.tauX * std::abs(e[i].x) + a.tauY * std::abs(e[i].y) + std::abs(m.v.z) * (a.tauX * b.tauY + a.tauY * b.tauX);
    }
    // Near the eye plane (W ~ 0) the split of r does not exist: the whole box is in the band.
    const bool nearEyePlane = !v[0].okW || !v[1].okW || !v[2].okW;
    const bool orientationUncertain = !(std::abs(det) > detBound);
    const int o = det > 0.0 ? 1 : -1;
    const glm::dvec3 normal = glm::cross(pd[1] - pd[0], pd[2] - pd[0]);
    const double volume = glm::dot(normal, pd[0]);
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x) {
        const size_t pixel = size_t(y) * c.width + size_t(x);
        if (nearEyePlane) {
          band[pixel] = 1;
          continue;
        }
        const glm::dvec3 kx(x, y, 1.0), moved = aInv * kx;
        const double dx = std::abs(moved.x / moved.z - x), dy = std::abs(moved.y / moved.z - y);
        int negative = 0, positive = 0, uncertain = 0, which = 0;
        for (int i = 0; i < 3; ++i) {
          const BandVertex &a = v[(i + 1) % 3], &b = v[(i + 2) % 3];
          const double value = double(o) * glm::dot(e[i], kx);
          const double bound = 6.0 * u * glm::dot(crossMag(a.absF, b.absF), kx) +
                               slack * glm::dot(crossMag(glm::abs(a.v), glm::abs(b.v)), kx) +
                               a.tauX * std::abs(b.v.y - y * b.v.z) + a.tauY * std::abs(x * b.v.z - b.v.x) +
                               b.tauX * std::abs(a.v.y - y * a.v.z) + b.tauY * std::abs(x * a.v.z - a.v.x) +
                               a.tauX * b.tauY + a.tauY * b.tauX + std::abs(e[i].x) * dx + std::abs(e[i].y) * dy;
          if (value < -bound) {
            ++negative;
          } else if (value > bound) {
            ++positive;
          } else {
            ++uncertain;
            which = i;
          }
        }
        // An orientation within rounding of zero may be either: out for both signs only where one
        // edge is certainly positive and another certainly negative (a sliver far from the pixel).
        if (orientationUncertain) {
          if (!(positive > 0 && negative > 0)) band[pixel] = 1;
          continue;
        }
        if (negative > 0) continue;                                                  // out, in both
        if (volume / glm::dot(normal, D * kx) < double(c.depth.x)) band[pixel] = 1;  // near the eye: boxes
        if (uncertain == 0) continue;                                                // in, in both
        if (uncertain >= 2) {
          band[pixel] = 1;
          continue;
        }
        const glm::vec3 ea = p[(which + 1) % 3], eb = p[(which + 2) % 3];
        const std::array<uint32_t, 3> ka = bitsOf(ea), kb = bitsOf(eb);
        const bool fromSmaller = ka < kb;
        EdgeRecord rec;
        const std::array<uint32_t, 3>&first = fromSmaller ? ka : kb, &second = fromSmaller ? kb : ka;
        std::copy(first.begin(), first.end(), rec.key.begin());
        std::copy(second.begin(), second.end(), rec.key.begin() + 3);
        rec.side = fromSmaller ? o : -o;
        records[pixel].push_back(rec);
      }
  }
  for (size_t i = 0; i < pixels; ++i) {
    const std::vector<EdgeRecord>& r = records[i];
    if (r.empty() || band[i]) continue;
    const bool negatedPair = r.size() == 2 && r[0].key == r[1].key && r[0].side == -r[1].side;
    if (!negatedPair) band[i] = 1;
  }
  return band;
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
