// CPU reference of 3D rasterization (Davidovič, Engelhardt, Georgiev, Slusallek, Dachsbacher 2012,
// "3D Rasterization", Sections 3.2-3.4), written so that a GLSL compute shader can mirror it
// operation for operation, and a double-precision ray cast to hold it to.
//
// The view is a pinhole: eye e and, for pixel (x, y) with integer x, y, the ray direction
//   d(x, y) = d0 + x·dx + y·dy
// through the pixel's CENTRE: the 0.5 is folded into d0 (d0 is the ray through the centre of pixel
// (0, 0)), so the edge functions are evaluated at integer (x, y), exact in float. x grows to the
// right, y downwards (Vulkan). d's forward component is 1, so a hit's ray parameter t is its view
// depth (−z_view, the w of clip space).
//
// Coverage is exactly the Plücker test of the float eye-relative vertices against the float rays:
// every edge function whose float value is within its rounding bound of zero is decided again in
// double and, if still within the double bound, exactly (expansion arithmetic). A centre exactly on
// an edge goes by the top-left rule of Section 3.4. Both faces are rasterized (the depth prepass
// draws with VK_CULL_MODE_NONE, gpu/raster_pipeline.cpp). So coverage does not depend on rounding:
// a closed mesh is watertight and a shared edge or vertex gives each pixel to one triangle.
#pragma once
#include <bit>
#include <cstdint>
#include <glm/glm.hpp>
#include <span>
#include <vector>

#include "scene/scene.h"

namespace hb {

// What the shader receives (gpu::Raster3dConstants holds the same values), all float. The double
// ray cast uses these same float values, so the two see identical rays.
struct Raster3dView {
  glm::vec3 eye{0.0f};  // world; vertices are made eye-relative in float (raster3d_ref.cpp says why)
  glm::vec3 d0{0.0f, 0.0f, -1.0f}, dx{0.0f}, dy{0.0f};  // d(x, y) = d0 + x·dx + y·dy, see above
  uint32_t width = 0, height = 0;                       // <= 2^16 each
  float znear = 0.1f, zfar = 1000.0f;                   // a hit is written only for znear <= t <= zfar
};

// The view of `camera` at width × height pixels, computed in double and rounded once (the same
// values as raster3dConstants in frame/passes/raster3d.cpp): pixel (x, y)'s centre has NDC
// (2(x + 0.5)/W − 1, 2(y + 0.5)/H − 1), view direction (ndc.x·a·tan(fov/2), −ndc.y·tan(fov/2), −1).
Raster3dView pinholeView(const Camera& camera, uint32_t width, uint32_t height);

// The per-pixel result packs (t bits << 32 | id) so that one 64-bit atomicMin keeps the nearest hit
// and, at equal t, the smaller triangle id. t is the view depth (> 0 for every hit, and positive
// floats order like their bits); the reverse-Z depth the hardware prepass stores is
// D/t − C (camera.h: C = zn/(zf − zn), D = zf·zn/(zf − zn)), strictly decreasing in t, so the
// smallest t is the largest reverse-Z depth (the prepass's GREATER_OR_EQUAL winner). t is packed
// rather than the depth because D/t − C rounds distinct t to one depth value far from the eye.
constexpr uint64_t kNoHit = ~uint64_t(0);
constexpr uint32_t kNoTriangle = ~uint32_t(0);
inline uint64_t packVisibility(float t, uint32_t id);
float visibilityDepth(uint64_t packed);  // t; +inf for kNoHit
inline uint32_t visibilityId(uint64_t packed) { return uint32_t(packed & 0xFFFFFFFFu); }

// Float setup of one triangle (what the shader keeps per triangle). Edge i is the edge opposite
// vertex i, from a = p[i+1] to b = p[i+2]; its row is (A_i, B_i, C_i) = orientation·(n_i·d0,
// n_i·dx, n_i·dy) with n_i = ((a + b)/2) × (a − b) (= b × a exactly), so the inside is V_i > 0.
struct Raster3dTriangle {
  glm::vec3 p[3];              // eye-relative vertices, float
  glm::vec3 rowA, rowB, rowC;  // V_i(x, y) = (A_i + x·B_i) + y·C_i, evaluated without fma
  glm::vec3 errA, errB, errC;  // |V_i − exact| <= kEdgeBoundFactor·((errA_i + x·errB_i) + y·errC_i) + kEdgeBoundFloor
  glm::ivec3 tieSign;          // exact sign of V_i at (x + ε, y + ε²): sign(B_i), or sign(C_i) if B_i = 0
  glm::ivec3 floatTieSign;     // the same from the float B_i, C_i (only without the fallback)
  glm::vec3 planeNormal;       // N = (p1 − p0) × (p2 − p0)
  float volume;                // N·p0 (= det[p0, p1, p2]); t = volume / (N·d)
  int orientation;             // +1: wound counter-clockwise seen from the eye (N faces it), −1: clockwise
};

struct Raster3dRefCounters {
  uint64_t triangles = 0;             // triangles given
  uint64_t degenerate = 0;            // of those, volume exactly 0 (zero area or the eye in their plane), or non-finite
  uint64_t setups = 0;                // set up with a non-empty screen box
  uint64_t orientationFallbacks = 0;  // triangles whose volume sign needed the exact evaluation
  uint64_t pixelsTested = 0;          // (triangle, pixel) pairs tested
  uint64_t edgeEvaluations = 0;       // 3 per pixel tested
  uint64_t fallbacks = 0;             // of those, re-evaluated in double (|V_float| <= its bound)
  uint64_t exactEvaluations = 0;      // of those, evaluated exactly (|V_double| <= its bound)
  uint64_t covered = 0;               // (triangle, pixel) pairs covered, whatever their depth
  uint64_t depthWrites = 0;           // covered pairs with znear <= t <= zfar (atomicMin calls)
};

struct Raster3dSettings {
  bool fp64Fallback = true;      // false: the plain float test (only to measure what the fallback prevents)
  bool fullScreenBoxes = false;  // test every pixel for every triangle (the result must not change)
};

struct Raster3dResult {
  uint32_t width = 0, height = 0;
  std::vector<uint64_t> visibility;  // per pixel (row-major): packVisibility(t, id), kNoHit = nothing
  std::vector<uint32_t> coverage;    // per pixel: triangles covering the centre, whatever their depth
  Raster3dRefCounters counters;
};

// Sets up triangle (w0, w1, w2) (world space) for `view`. Returns false if it can never cover a
// pixel: its volume is exactly 0 (zero area, or the eye in its plane) or a vertex is not finite.
// Precondition: eye-relative coordinates below 2^40 in magnitude (asserted).
bool setupTriangle3d(const Raster3dView& view, glm::vec3 w0, glm::vec3 w1, glm::vec3 w2, Raster3dTriangle& tri,
                     Raster3dRefCounters& counters);

// Does the triangle cover the centre of pixel (x, y)? If so, t = its view depth and lambda its
// barycentrics λ_i = V_i / ΣV_j (paper, 3.2).
bool coversPixel3d(const Raster3dView& view, const Raster3dTriangle& tri, uint32_t x, uint32_t y, bool fp64Fallback,
                   float& t, glm::vec3& lambda, Raster3dRefCounters& counters);

// The pixel box [lo, hi] (inclusive, clamped to the image; empty if hi < lo) of every pixel whose
// ray can hit the triangle at t >= znear/2: the bound of the projection of the part of the
// triangle in front of that plane, plus one pixel. Computed in double from eye-relative vertices.
void screenBox3d(const Raster3dView& view, const glm::dvec3 p[3], glm::ivec2& lo, glm::ivec2& hi);

// Rasterizes triangles k = (indices[3k], indices[3k+1], indices[3k+2]) of `positions` (world xyz,
// float); triangle k's id is k. Precondition: indices.size() % 3 == 0, every index < positions.size().
// Coverage is complete for hits at t >= znear/2 (the screen box), or every t > 0 with fullScreenBoxes.
Raster3dResult rasterize3d(const Raster3dView& view, std::span<const glm::vec3> positions,
                           std::span<const uint32_t> indices, const Raster3dSettings& settings = {});

// Per pixel, the same rays (float view constants, evaluated in double) against the triangles in
// double from their float world vertices (eye-relative in double, no rounding to float): edge
// functions in double with the same top-left rule at exact zeros, nearest t in [znear, zfar],
// ties to the smaller id. coverage counts every triangle hit at t >= znear/2, as rasterize3d.
struct RayCastHit {
  uint32_t id = kNoTriangle;
  double t = 0.0;
};
struct RayCastResult {
  uint32_t width = 0, height = 0;
  std::vector<RayCastHit> nearest;
  std::vector<uint32_t> coverage;
};
RayCastResult rayCast3d(const Raster3dView& view, std::span<const glm::vec3> positions,
                        std::span<const uint32_t> indices);

// The exact sign (−1, 0, +1) of (b × a)·(c[0] + ... + c[count−1]) for float a, b and double c[k]
// that are exact (a float, or an integer times a float). count <= 3. Expansion arithmetic:
// Shewchuk 1997, Two-Sum, Two-Product (fma) and Grow-Expansion with zero elimination.
int exactTripleProductSign(glm::vec3 b, glm::vec3 a, const glm::dvec3* c, int count);

// V_i of edge (a, b) (un-oriented: (b × a)·d(x, y)) in double from the float inputs, as the fp64
// fallback computes it; bound: |result − exact| <= bound (raster3d_ref.cpp derives it).
double edgeFunctionDouble(const Raster3dView& view, glm::vec3 a, glm::vec3 b, uint32_t x, uint32_t y, double& bound);

// The float evaluation's error bound (raster3d_ref.cpp derives it): 16 u with u = 2^-24, and a
// floor for products that underflow.
constexpr float kEdgeBoundFactor = 16.0f * 5.9604644775390625e-8f;   // 16 · 2^-24
constexpr float kEdgeBoundFloor = 7.52316384526264e-37f;             // 2^-120
constexpr double kEdgeBoundFactorD = 16.0 * 1.1102230246251565e-16;  // 16 · 2^-53

inline uint64_t packVisibility(float t, uint32_t id) { return (uint64_t(std::bit_cast<uint32_t>(t)) << 32) | id; }

}  // namespace hb
