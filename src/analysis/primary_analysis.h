// Primary visibility against its exact counterpart (docs/frame.md "References"): a double-precision
// ray cast per pixel (reference/bvh: watertight, both faces) along the same pixel-centre rays the
// 3D rasterizer uses, t in [znear, zfar]. Per pixel the rasterizer's triangle id and view depth t
// are compared with the ray cast's.
#pragma once
#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "reference/bvh.h"
#include "reference/raster3d_ref.h"
#include "scene/scene.h"
#include "shared/gpu_types.h"

namespace hb {

struct PrimaryComparison {
  uint64_t pixels = 0;
  uint64_t bothHit = 0, idsEqual = 0;
  uint64_t holes = 0;     // the ray cast hits, the rasterizer reports nothing
  uint64_t spurious = 0;  // the rasterizer reports a triangle, the ray cast hits none
  uint64_t idMismatches = 0;
  // Of holes, spurious pixels and id mismatches: those that are not ties. A tie: the pixel's ray
  // passes within kTieMargin (barycentric) of an edge of the triangle involved, or both hits lie
  // within kTieDepth (relative t) of each other (coincident or touching surfaces).
  uint64_t notTies = 0;
  double depthRelP999 = 0, depthRelMax = 0;  // |t_gpu - t_cpu| / t_cpu where the ids are equal
};

// Tie thresholds. A float vertex is within u = 2^-24 relative of the double one, and 3DR works on
// eye-relative float vertices (one more rounding): a barycentric coordinate of the rasterizer's
// geometry differs from the exact one by about (|p| / edge length) · 4u. 1e-4 allows edges 100x
// shorter than their distance to the eye (kTieMargin); kTieDepth is 64u relative.
// Relative to what: positions are rounded relative to the eye, so a hit's t carries an absolute
// error of a few u times the hit's distance from the eye. For rays from the eye that distance is
// t·|d| ~ t; an orthographic ray starts up to |o − eye| (half the view) off the eye, so its t is
// held to kTieDepth·max(t, |o − eye|) (tieScale), which is t for every view from the eye.
constexpr double kTieMargin = 1e-4;
constexpr double kTieDepth = 64.0 * 5.9604644775390625e-8;
inline double tieScale(double t, double originOffset) { return t > originOffset ? t : originOffset; }

// vis: the rasterizer's key per pixel (t bits << 32 | id, ~0 = nothing); rays: its constants.
PrimaryComparison comparePrimary(const Bvh& bvh, const std::vector<uint64_t>& vis, const gpu::Raster3dConstants& rays);

nlohmann::json toJson(const PrimaryComparison& c);

// Coverage counted additively against the exact 3D rasterization (reference/raster3d_ref: the same
// float rays and vertices, every edge function's sign decided exactly, the same tie rule), per
// pixel: how many triangles the method gives the pixel's centre to, against how many it belongs
// to. More: a double cover (an edge or vertex claimed by two triangles that share it, or a rounding
// error that lets a triangle spill); fewer: a hole. Both counts include every depth (a hidden double
// cover is still one); pixels are counted once however many triangles differ.
struct CoverageComparison {
  uint64_t pixels = 0, coveredPixels = 0;  // covered: the exact count is > 0
  uint64_t doubleCovers = 0, holes = 0;
  // Given a rounding band (raster2dRoundingBand): the pixels it allows to differ, and of the pixels
  // with a double cover or a hole those it does not allow (0 unless the method breaks its derivation).
  uint64_t bandPixels = 0, outsideBand = 0;
};
// The view the shader's constants describe (the same eye, float rays and depth range): what the
// exact CPU rasterization (rasterize3d) takes to decide the GPU's own samples.
Raster3dView raster3dViewOf(const gpu::Raster3dConstants& rays);

// method: per pixel, (triangle, pixel) pairs covered (Raster3dPass::readCoverage). band: optional,
// per pixel nonzero where the method's count may differ from the exact one.
CoverageComparison compareCoverage(const Scene& scene, const gpu::Raster3dConstants& rays,
                                   const std::vector<uint32_t>& method, const std::vector<uint8_t>* band = nullptr);

// Where 2D homogeneous rasterization (primary=2dr: raster3d.glsl.inc r2dSetup, float only, no fp64
// fallback) may give a pixel another coverage count than the exact 3D rasterization above: per
// pixel 1 if some triangle's float decision there can differ from the exact one in a way that
// changes the count (near a vertex, an edge not shared with a triangle that negates it exactly,
// an orientation within rounding of zero, or a hit nearer than znear where the screen boxes
// differ), else 0. primary_analysis.cpp derives the bound. Precondition: a perspective view.
std::vector<uint8_t> raster2dRoundingBand(const Scene& scene, const gpu::Raster3dConstants& rays);
nlohmann::json toJson(const CoverageComparison& c);

}  // namespace hb
