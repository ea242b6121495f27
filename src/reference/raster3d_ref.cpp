#include "reference/raster3d_ref.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "base/errors.h"

// The float arithmetic below is the shader's, rounded after every operation: products are never
// fused into sums (GLSL `precise`, SPIR-V NoContraction; Vulkan rounds fp32 add, sub and mul
// correctly, so a conformant GPU gives these bits). GCC contracts a*b + c into an fma only where
// the target has one; then contraction is switched off here. raster3d_ref_accuracy_test.cpp checks it.
#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#elif defined(__GNUC__) && defined(__FP_FAST_FMAF)
#pragma GCC optimize("fp-contract=off")
#endif

namespace hb {

// Why the vertices are made eye-relative in float (p = fl(w − e), once per vertex):
// - With the eye at the origin V_i(d) = n_i·d is linear in (x, y) with no per-pixel e term (paper
//   3.2), and every rounding error below scales with |p| (the distance from the eye), not with the
//   distance from the world origin, which can be far larger than the scene's extent.
// - The shader runs the setup in float (its world vertices are float), and the one rounding
//   |fl(w − e) − (w − e)| <= u·|w − e| per coordinate is the same for every triangle that uses the
//   vertex, so triangles sharing a vertex share its eye-relative value bit for bit: the
//   precondition of the midpoint form's symmetry and of the exact decision below. It moves the
//   geometry by at most u·|p| (relative to the double ray cast, which does not round there).
//
// Error bound of the float edge function (u = 2^-24, round to nearest, no fma, no underflow;
// γ_k = k·u/(1 − k·u), and (1 + γ_j)(1 + γ_k) <= 1 + γ_{j+k}: Higham, Accuracy and Stability of
// Numerical Algorithms, 2nd ed., Lemma 3.3). The inputs a, b (eye-relative floats), d0, dx, dy
// (floats) and the integers x, y <= 2^16 are exact; the exact edge function of these inputs is
//   M = (a + b)/2, E = a − b, N = M × E (= b × a), V* = N·(d0 + x·dx + y·dy) = A* + x·B* + y·C*.
// Let G_l = |M_{l+1}·E_{l+2}| + |M_{l+2}·E_{l+1}| (the two terms of N_l) and
//   E_A = Σ_l G_l·|d0_l|,  E_B = Σ_l G_l·|dx_l|,  E_C = Σ_l G_l·|dy_l|.
// 1. m = fl(fl(a + b)·0.5) = M(1 + δ), e = fl(a − b) = E(1 + δ) (·0.5 is exact); t1, t2 = fl(m·e)
//    carry 3 factors (1 + δ), n_l = fl(t1 − t2) a fourth: |n_l − N_l| <= γ_4·G_l, |n_l| <= (1 + γ_4)·G_l.
// 2. A = fl((n_x·d0_x + n_y·d0_y) + n_z·d0_z): |A − n·d0| <= γ_3·Σ_l |n_l||d0_l| (Higham 3.1), so
//    |A − A*| <= (γ_3(1 + γ_4) + γ_4)·E_A <= γ_7·E_A and |A| <= (1 + γ_7)·E_A; likewise B and C.
// 3. V = fl(fl(A + fl(x·B)) + fl(y·C)): |V − (A + x·B + y·C)| <= γ_3·(|A| + x|B| + y|C|).
//    Together: |V − V*| <= (γ_7 + γ_3(1 + γ_7))·(E_A + x·E_B + y·E_C) <= γ_10·(E_A + x·E_B + y·E_C).
// 4. The bound is evaluated in float from the computed t1, t2: mag_l = fl(|t1| + |t2|) >=
//    (1 − u)^4·G_l, errA = fl(Σ mag_l·|d0_l|) >= (1 − u)^7·E_A (sums of non-negative terms in any
//    order, fused or not, lose at most a factor (1 − u) per operation), and the per-pixel
//    16u·fl(fl(errA + x·errB) + y·errC) >= 16u·(1 − u)^11·(E_A + x·E_B + y·E_C) > γ_10·(...).
// 5. Underflow: a product below 2^-126 has an absolute error up to 2^-150 (sums are exact there).
//    With |d0|, |dx|, |dy| components <= 2^8 and x, y <= 2^16 the 17 products of one evaluation add
//    less than 2^-120 = kEdgeBoundFloor. Eye-relative coordinates < 2^40 keep every value finite.
// So |V| > bound decides the sign of V*; otherwise the fallback decides it (fp64, then exact).
//
// The fp64 re-evaluation (same float inputs, u_d = 2^-53) computes d = fl(fl(d0 + x·dx) + y·dy)
// (x·dx is exact in double) and V = fl(n·d) with n as in 1:
//   |d_l − D_l| <= γ_2·H_l, H_l = |d0_l| + x|dx_l| + y|dy_l|, and
//   |V − V*| <= γ_3·Σ|n_l||d_l| + Σ|n_l||d_l − D_l| + Σ|n_l − N_l||D_l| <= γ_9·Σ_l G_l·H_l,
// where Σ_l G_l·H_l = E_A + x·E_B + y·E_C again. H_l, not |d_l|: d_l may cancel. 16·u_d covers γ_9
// and the rounding of the bound as in 4; nothing underflows in double (the smallest product of
// three floats is 2^-447).

namespace {

float dotF(glm::vec3 a, glm::vec3 b) { return (a.x * b.x + a.y * b.y) + a.z * b.z; }
double dotD(glm::dvec3 a, glm::dvec3 b) { return (a.x * b.x + a.y * b.y) + a.z * b.z; }
int signOf(double v) { return (v > 0.0) - (v < 0.0); }

// Edge normal of the edge from a to b, midpoint form (paper 3.4): both triangles of a shared edge
// compute the same m (float + commutes) and e = a − b = −(b − a) exactly, and round-to-nearest is
// symmetric in sign, so their normals (and every row below) are exact negations.
glm::vec3 edgeNormalF(glm::vec3 a, glm::vec3 b, glm::vec3& magnitude) {
  const glm::vec3 m = (a + b) * 0.5f;
  const glm::vec3 e = a - b;
  const glm::vec3 t1(m.y * e.z, m.z * e.x, m.x * e.y);
  const glm::vec3 t2(m.z * e.y, m.x * e.z, m.y * e.x);
  magnitude = glm::abs(t1) + glm::abs(t2);
  return t1 - t2;
}

}  // namespace

// V_i(x, y) in double from the same float inputs (oriented by the caller); bound as derived above.
double edgeFunctionDouble(const Raster3dView& view, glm::vec3 af, glm::vec3 bf, uint32_t xi, uint32_t yi,
                          double& bound) {
  const double x = xi, y = yi;
  const glm::dvec3 a(af), b(bf);
  const glm::dvec3 m = (a + b) * 0.5;
  const glm::dvec3 e = a - b;
  const glm::dvec3 t1(m.y * e.z, m.z * e.x, m.x * e.y);
  const glm::dvec3 t2(m.z * e.y, m.x * e.z, m.y * e.x);
  const glm::dvec3 n = t1 - t2;
  const glm::dvec3 d0(view.d0), dx(view.dx), dy(view.dy);
  const glm::dvec3 d = (d0 + x * dx) + y * dy;
  const glm::dvec3 h = (glm::abs(d0) + x * glm::abs(dx)) + y * glm::abs(dy);
  bound = kEdgeBoundFactorD * dotD(glm::abs(t1) + glm::abs(t2), h);
  return dotD(n, d);
}

namespace {

// Expansion arithmetic (Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast Robust
// Geometric Predicates", 1997): Two-Sum (Theorem 7) and Two-Product (here with fma, whose error
// term is exact) are error-free; Grow-Expansion (Theorem 10) adds a double to a nonoverlapping
// expansion exactly, and zero elimination keeps it nonoverlapping. The sign of a nonoverlapping
// expansion is that of its largest component, the last one. Needs round-to-nearest-even and no
// overflow or underflow (products of at most three floats and an integer: neither can happen).
// A shader may use Dekker's split instead of fma: the exact sum, and so the sign, is the same.
double twoSum(double a, double b, double& err) {
  const double s = a + b;
  const double bv = s - a;
  const double av = s - bv;
  err = (a - av) + (b - bv);
  return s;
}

int growExpansion(double* e, int n, double b) {
  double q = b;
  int m = 0;
  for (int i = 0; i < n; ++i) {
    double h;
    q = twoSum(q, e[i], h);
    if (h != 0.0) e[m++] = h;
  }
  if (q != 0.0) e[m++] = q;
  return m;
}

// Exact sign of V_i(x, y) of edge (a, b): (b × a)·(d0 + x·dx + y·dy), x·dx exact in double.
int edgeExactSign(glm::vec3 a, glm::vec3 b, const Raster3dView& view, double x, double y) {
  const glm::dvec3 c[3] = {glm::dvec3(view.d0), x * glm::dvec3(view.dx), y * glm::dvec3(view.dy)};
  return exactTripleProductSign(b, a, c, 3);
}

// The sign of V* with its float value v and bound: exact whenever |v| > bound.
int certainSign(float v, float bound, glm::vec3 b, glm::vec3 a, const glm::dvec3& c) {
  if (std::fabs(v) > bound) return signOf(v);
  return exactTripleProductSign(b, a, &c, 1);
}

}  // namespace

int exactTripleProductSign(glm::vec3 b, glm::vec3 a, const glm::dvec3* c, int count) {
  HB_ASSERT(count >= 1 && count <= 3);
  double e[36];
  int m = 0;
  for (int l = 0; l < 3; ++l) {
    // (b × a)_l = b_{l+1}·a_{l+2} − b_{l+2}·a_{l+1}: each product of two floats is exact in double.
    const int l1 = (l + 1) % 3, l2 = (l + 2) % 3;
    const double terms[2] = {double(b[l1]) * double(a[l2]), -(double(b[l2]) * double(a[l1]))};
    for (const double term : terms)
      for (int k = 0; k < count; ++k) {
        const double hi = term * c[k][l];
        const double lo = std::fma(term, c[k][l], -hi);
        m = growExpansion(e, m, lo);
        m = growExpansion(e, m, hi);
      }
  }
  return m == 0 ? 0 : signOf(e[m - 1]);
}

float visibilityDepth(uint64_t packed) {
  if (packed == kNoHit) return std::numeric_limits<float>::infinity();
  return std::bit_cast<float>(uint32_t(packed >> 32));
}

Raster3dView pinholeView(const Camera& camera, uint32_t width, uint32_t height) {
  HB_ASSERT(width > 0 && height > 0 && width <= 65536 && height <= 65536);
  const glm::dmat4 viewInv = glm::inverse(glm::dmat4(camera.view));
  const glm::dvec3 right(viewInv[0]), up(viewInv[1]), back(viewInv[2]), eye(viewInv[3]);
  const double w = width, h = height, a = w / h, tanHalf = std::tan(double(camera.yfov) * 0.5);
  const glm::dvec3 d0 = -back + right * ((-1.0 + 1.0 / w) * a * tanHalf) + up * ((1.0 - 1.0 / h) * tanHalf);
  Raster3dView v;
  v.eye = glm::vec3(eye);
  v.d0 = glm::vec3(d0);
  v.dx = glm::vec3(right * (2.0 * a * tanHalf / w));
  v.dy = glm::vec3(-up * (2.0 * tanHalf / h));
  v.width = width;
  v.height = height;
  v.znear = camera.znear;
  v.zfar = camera.zfar;
  return v;
}

bool setupTriangle3d(const Raster3dView& view, glm::vec3 w0, glm::vec3 w1, glm::vec3 w2, Raster3dTriangle& tri,
                     Raster3dRefCounters& counters) {
  tri = {};
  tri.p[0] = w0 - view.eye;
  tri.p[1] = w1 - view.eye;
  tri.p[2] = w2 - view.eye;
  for (const glm::vec3& p : tri.p) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      ++counters.degenerate;
      return false;
    }
    HB_ASSERT(std::fabs(p.x) < 0x1p40f && std::fabs(p.y) < 0x1p40f && std::fabs(p.z) < 0x1p40f);
  }
  // Orientation from the volume det[p0, p1, p2] = N·p0 (N from the edges: its terms are
  // |p1 − p0|·|p2 − p0|, not |p|², so det, and t below, keep their digits for small triangles).
  // Error: e1, e2 one rounding each, N_l a γ_4 of its terms, the dot a γ_3: |det − det*| <=
  // γ_7·Σ_l GN_l·|p0_l|, with GN_l the terms' magnitudes; 16u covers it as in 4 above. Underflow
  // as in 5, but the products' absolute errors (2^-150) are multiplied by |p0_l| < 2^40: 2^-100.
  const glm::vec3 e1 = tri.p[1] - tri.p[0], e2 = tri.p[2] - tri.p[0];
  const glm::vec3 s1(e1.y * e2.z, e1.z * e2.x, e1.x * e2.y), s2(e1.z * e2.y, e1.x * e2.z, e1.y * e2.x);
  tri.planeNormal = s1 - s2;
  tri.volume = dotF(tri.planeNormal, tri.p[0]);
  const float volumeBound = kEdgeBoundFactor * dotF(glm::abs(s1) + glm::abs(s2), glm::abs(tri.p[0])) + 0x1p-100f;
  int det = signOf(tri.volume);
  if (!(std::fabs(tri.volume) > volumeBound)) {
    ++counters.orientationFallbacks;
    const glm::dvec3 p0(tri.p[0]);
    det = exactTripleProductSign(tri.p[1], tri.p[2], &p0, 1);  // (p1 × p2)·p0
  }
  if (det == 0) {  // zero area, or the eye in the triangle's plane: covers no pixel
    ++counters.degenerate;
    return false;
  }
  // The paper's volume V = p0·n0 = p0·(p2 × p1) = −det: a ray hits iff every V_i has V's sign, so
  // the rows are multiplied by orientation = sign(V) and the inside is V_i > 0 for both faces.
  tri.orientation = -det;
  const float o = float(tri.orientation);
  const glm::dvec3 dx(view.dx), dy(view.dy);
  for (int i = 0; i < 3; ++i) {
    const glm::vec3 a = tri.p[(i + 1) % 3], b = tri.p[(i + 2) % 3];
    glm::vec3 mag;
    const glm::vec3 n = edgeNormalF(a, b, mag);
    const float rowB = dotF(n, view.dx), rowC = dotF(n, view.dy);
    tri.rowA[i] = o * dotF(n, view.d0);
    tri.rowB[i] = o * rowB;
    tri.rowC[i] = o * rowC;
    tri.errA[i] = dotF(mag, glm::abs(view.d0));
    tri.errB[i] = dotF(mag, glm::abs(view.dx));
    tri.errC[i] = dotF(mag, glm::abs(view.dy));
    // The top-left rule (paper 3.4) is the sign of V_i at the centre moved by (ε, ε²), ε → 0: the
    // same point for every triangle, so shared edges and vertices go to exactly one triangle. It
    // needs the exact signs of B_i and C_i (a wrong sign would move the point differently for
    // different edges); B_i is within γ_7·E_B of exact (step 2 above). B_i = C_i = 0 exactly only
    // if n_i = 0, i.e. a degenerate triangle.
    const int b0 = certainSign(rowB, kEdgeBoundFactor * tri.errB[i] + kEdgeBoundFloor, b, a, dx);
    const int c0 = b0 != 0 ? 0 : certainSign(rowC, kEdgeBoundFactor * tri.errC[i] + kEdgeBoundFloor, b, a, dy);
    tri.tieSign[i] = tri.orientation * (b0 != 0 ? b0 : c0);
    tri.floatTieSign[i] = tri.rowB[i] != 0.0f ? signOf(tri.rowB[i]) : signOf(tri.rowC[i]);
  }
  return true;
}

bool coversPixel3d(const Raster3dView& view, const Raster3dTriangle& tri, uint32_t x, uint32_t y, bool fp64Fallback,
                   float& t, glm::vec3& lambda, Raster3dRefCounters& counters) {
  const float fx = float(x), fy = float(y);  // exact: x, y <= 2^16
  glm::vec3 v(0.0f);
  bool inside = true;
  for (int i = 0; i < 3; ++i) {
    v[i] = (tri.rowA[i] + fx * tri.rowB[i]) + fy * tri.rowC[i];
    int s = signOf(v[i]);
    if (fp64Fallback) {
      const float bound = kEdgeBoundFactor * ((tri.errA[i] + fx * tri.errB[i]) + fy * tri.errC[i]) + kEdgeBoundFloor;
      if (!(std::fabs(v[i]) > bound)) {
        ++counters.fallbacks;
        const glm::vec3 a = tri.p[(i + 1) % 3], b = tri.p[(i + 2) % 3];
        double boundD;
        const double vd = edgeFunctionDouble(view, a, b, x, y, boundD);
        if (std::fabs(vd) > boundD) {
          s = tri.orientation * signOf(vd);
        } else {
          ++counters.exactEvaluations;
          s = tri.orientation * edgeExactSign(a, b, view, double(x), double(y));
        }
      }
      if (s == 0) s = tri.tieSign[i];
    } else if (s == 0) {
      s = tri.floatTieSign[i];
    }
    inside = inside && s > 0;  // all three are evaluated, as the shader does (the counters match)
  }
  counters.edgeEvaluations += 3;
  ++counters.pixelsTested;
  if (!inside) return false;
  // t = V / ΣV_i (paper 3.2) with ΣV_i(d) = (Σ n_i)·d = −N·d and V = −det: t = det / (N·d). The sum
  // is taken as N·d because Σ n_i in float keeps only the digits that the n_i (terms ~|p|·|edge|)
  // leave of N (terms ~|edge|²). λ_i = V_i / ΣV_j from the float V_i.
  const glm::vec3 d = (view.d0 + fx * view.dx) + fy * view.dy;
  t = tri.volume / dotF(tri.planeNormal, d);
  lambda = v / ((v.x + v.y) + v.z);
  return true;
}

void screenBox3d(const Raster3dView& view, const glm::dvec3 p[3], glm::ivec2& lo, glm::ivec2& hi) {
  HB_ASSERT(view.znear > 0.0f);
  // q = [dx dy d0]^-1·p: p = q.z·d(q.x/q.z, q.y/q.z), so q.z is the view depth of p and
  // (q.x, q.y)/q.z its pixel coordinates.
  const glm::dmat3 toPixel = glm::inverse(glm::dmat3(glm::dvec3(view.dx), glm::dvec3(view.dy), glm::dvec3(view.d0)));
  const double zc = 0.5 * double(view.znear);
  glm::dvec3 q[3];
  for (int i = 0; i < 3; ++i) q[i] = toPixel * p[i];
  glm::dvec2 qmin(std::numeric_limits<double>::infinity()), qmax(-std::numeric_limits<double>::infinity());
  auto add = [&](const glm::dvec3& r) {
    const glm::dvec2 px = glm::dvec2(r) / r.z;
    qmin = glm::min(qmin, px);
    qmax = glm::max(qmax, px);
  };
  for (int i = 0; i < 3; ++i) {  // Sutherland-Hodgman on the plane q.z = zc
    const glm::dvec3 a = q[i], b = q[(i + 1) % 3];
    if (a.z >= zc) add(a);
    if ((a.z >= zc) != (b.z >= zc)) {
      glm::dvec3 c = a + (b - a) * ((zc - a.z) / (b.z - a.z));
      c.z = zc;
      add(c);
    }
  }
  lo = glm::ivec2(0);
  hi = glm::ivec2(int(view.width) - 1, int(view.height) - 1);
  if (!(qmin.x <= qmax.x && qmin.y <= qmax.y)) {  // nothing in front of the plane (or NaN)
    hi = glm::ivec2(-1);
    return;
  }
  // One pixel of margin: the box's rounding is ~1e-10 px; the edge functions decide exactly.
  const glm::dvec2 limit(view.width + 1.0, view.height + 1.0);
  const glm::dvec2 a = glm::clamp(qmin, glm::dvec2(-2.0), limit), b = glm::clamp(qmax, glm::dvec2(-2.0), limit);
  lo = glm::max(lo, glm::ivec2(glm::floor(a)) - 1);
  hi = glm::min(hi, glm::ivec2(glm::ceil(b)) + 1);
}

namespace {

void checkView(const Raster3dView& view) {
  HB_ASSERT(view.width > 0 && view.height > 0 && view.width <= 65536 && view.height <= 65536);
  for (const glm::vec3& c : {view.d0, view.dx, view.dy})  // the underflow floor (5 above) assumes it
    HB_ASSERT(std::fabs(c.x) <= 256.0f && std::fabs(c.y) <= 256.0f && std::fabs(c.z) <= 256.0f);
}

}  // namespace

Raster3dResult rasterize3d(const Raster3dView& view, std::span<const glm::vec3> positions,
                           std::span<const uint32_t> indices, const Raster3dSettings& settings) {
  checkView(view);
  HB_ASSERT(indices.size() % 3 == 0 && indices.size() / 3 < kNoTriangle);
  Raster3dResult r;
  r.width = view.width;
  r.height = view.height;
  r.visibility.assign(size_t(view.width) * view.height, kNoHit);
  r.coverage.assign(size_t(view.width) * view.height, 0u);
  Raster3dRefCounters& c = r.counters;
  for (size_t k = 0; k < indices.size() / 3; ++k) {
    ++c.triangles;
    const uint32_t i0 = indices[3 * k], i1 = indices[3 * k + 1], i2 = indices[3 * k + 2];
    HB_ASSERT(i0 < positions.size() && i1 < positions.size() && i2 < positions.size());
    Raster3dTriangle tri;
    if (!setupTriangle3d(view, positions[i0], positions[i1], positions[i2], tri, c)) continue;
    glm::ivec2 lo(0), hi(int(view.width) - 1, int(view.height) - 1);
    if (!settings.fullScreenBoxes) {
      const glm::dvec3 p[3] = {glm::dvec3(tri.p[0]), glm::dvec3(tri.p[1]), glm::dvec3(tri.p[2])};
      screenBox3d(view, p, lo, hi);
    }
    if (hi.x < lo.x || hi.y < lo.y) continue;
    ++c.setups;
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x) {
        float t;
        glm::vec3 lambda;
        if (!coversPixel3d(view, tri, uint32_t(x), uint32_t(y), settings.fp64Fallback, t, lambda, c)) continue;
        const size_t pixel = size_t(y) * view.width + size_t(x);
        ++c.covered;
        ++r.coverage[pixel];
        if (!(t >= view.znear && t <= view.zfar)) continue;  // the near and far planes (and NaN)
        ++c.depthWrites;
        r.visibility[pixel] = std::min(r.visibility[pixel], packVisibility(t, uint32_t(k)));
      }
  }
  return r;
}

RayCastResult rayCast3d(const Raster3dView& view, std::span<const glm::vec3> positions,
                        std::span<const uint32_t> indices) {
  checkView(view);
  HB_ASSERT(indices.size() % 3 == 0);
  RayCastResult r;
  r.width = view.width;
  r.height = view.height;
  r.nearest.assign(size_t(view.width) * view.height, RayCastHit{});
  r.coverage.assign(size_t(view.width) * view.height, 0u);
  const glm::dvec3 eye(view.eye), d0(view.d0), dx(view.dx), dy(view.dy);
  for (size_t k = 0; k < indices.size() / 3; ++k) {
    glm::dvec3 p[3];
    for (int i = 0; i < 3; ++i) p[i] = glm::dvec3(positions[indices[3 * k + i]]) - eye;
    const glm::dvec3 normal = glm::cross(p[1] - p[0], p[2] - p[0]);
    const double det = glm::dot(normal, p[0]);
    if (!(det != 0.0)) continue;
    const double o = det > 0.0 ? -1.0 : 1.0;
    glm::dvec3 n[3];
    for (int i = 0; i < 3; ++i) {  // midpoint form in double: shared edges stay exact negations
      const glm::dvec3 a = p[(i + 1) % 3], b = p[(i + 2) % 3];
      n[i] = o * glm::cross((a + b) * 0.5, a - b);
    }
    glm::ivec2 lo, hi;
    screenBox3d(view, p, lo, hi);
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x) {
        const glm::dvec3 d = (d0 + double(x) * dx) + double(y) * dy;
        bool inside = true;
        for (int i = 0; i < 3 && inside; ++i) {
          const double v = glm::dot(n[i], d);
          const double tie = glm::dot(n[i], dx) != 0.0 ? glm::dot(n[i], dx) : glm::dot(n[i], dy);
          inside = v > 0.0 || (v == 0.0 && tie > 0.0);
        }
        if (!inside) continue;
        const double t = det / glm::dot(normal, d);
        const size_t pixel = size_t(y) * view.width + size_t(x);
        ++r.coverage[pixel];
        if (!(t >= view.znear && t <= view.zfar)) continue;
        RayCastHit& best = r.nearest[pixel];
        if (best.id == kNoTriangle || t < best.t || (t == best.t && k < best.id)) best = {uint32_t(k), t};
      }
  }
  return r;
}

}  // namespace hb
