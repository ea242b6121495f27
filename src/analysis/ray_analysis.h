// Analysis of a shadow frame on the CPU (design.md "Accuracy", "The oracle"): where every candidate
// (pixel, light) pair went, the fewest rays any culler could trace, how accurate the reconstructed
// normals and world positions are, and a CPU shadow reference that repeats the GPU's decisions.
// Images are row-major, width × height, top row first; depth 0 = sky.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "reference/bvh.h"
#include "base/image_io.h"
#include "reference/reconstruct_ref.h"
#include "frame/renderer.h"
#include "scene/scene.h"

namespace hb {

// ---- ray accounting ---------------------------------------------------------------------------

// One pixel's accounting texel (4 words, gpu_types.h kAccount*), unpacked.
struct PixelAccount {
  uint32_t traced = 0, listed = 0, byNormal = 0, byRange = 0, atLight = 0, noShadow = 0;
};
PixelAccount unpackAccount(const uint32_t* texel);

// Totals over the non-sky pixels. Every candidate pair lands in exactly one bucket:
//   candidates = culledByTile + droppedByOverflow + culledByZbin + culledByRange + culledByNormal
//                + atLight + noShadow + traced.
struct RayAccounting {
  uint64_t candidates = 0;         // non-sky pixels × scene lights
  uint64_t culledByTile = 0;       // per pixel: scene lights − its tile's total
  uint64_t droppedByOverflow = 0;  // per pixel: tile total − tile count (capacity exceeded; tile lists only)
  uint64_t culledByZbin = 0;       // per pixel: its tile's lights outside its z-bin's range (zbin only)
  uint64_t culledByRange = 0, culledByNormal = 0, atLight = 0, noShadow = 0, traced = 0;
  // Pixels whose GPU walk visited another number of lights than the readback's slice: must be 0.
  uint64_t walkMismatches = 0;
  std::vector<uint32_t> perPixel;   // traced rays per pixel (0 for sky), width*height
  std::vector<uint64_t> histogram;  // [k] = non-sky pixels that traced k rays; size = the most + 1
  uint64_t bucketSum() const;
  void addCounts(const RayAccounting& other);  // every count (not perPixel, histogram)
  bool addsUp() const { return candidates == bucketSum() && walkMismatches == 0; }
};

// Preconditions: depth has width*height entries, shadows.accounting 4 per pixel; culling is the
// grid the shadow pass read (tilesX = ceil(width / tileSize), …); every tile total <= sceneLightCount.
RayAccounting accountRays(const ShadowReadback& shadows, const CullingReadback& culling,
                          const std::vector<float>& depth, uint32_t width, uint32_t height, uint32_t tileSize,
                          uint32_t sceneLightCount);
// Keys: candidates, culled_by_tile, dropped_by_overflow, culled_by_zbin, culled_by_range,
// culled_by_normal, at_light, no_shadow, traced, walk_mismatches, per_pixel_histogram.
nlohmann::json toJson(const RayAccounting& rays);

// Heatmap of per-pixel ray counts in the thesis's colours (image_io.h heatmapThesis); red =
// maxValue (rayHeatmapMax).
ImageRGBA8 rayHeatmap(const std::vector<uint32_t>& perPixel, uint32_t width, uint32_t height, uint32_t maxValue);
// Red of the ray heatmaps: capped tile lists min(sceneLightCount, 32), the most rays a pixel can
// trace; uncapped lists the most any pixel of `perPixel` traced (at least 1).
uint32_t rayHeatmapMax(bool capped, uint32_t sceneLightCount, const std::vector<uint32_t>& perPixel);

// ---- the true surface seen by each pixel --------------------------------------------------------

enum class SurfaceState : uint8_t {
  Sky,        // depth 0: nothing rasterised
  Matched,    // the eye ray hits a triangle at the rasterised depth (within the window below)
  Unmatched,  // rasterised, but the eye ray through the pixel centre finds no triangle there
              // (silhouette pixels where rasteriser and ray disagree): no reference normal
};
// Relative distance window in which a triangle hit along the eye ray counts as the rasterised
// surface: the depth buffer's distance is within ~16 float ulps (depth_prepass_test), i.e.
// 1e-6 relative; 1e-4 is wide enough for that and narrow enough to separate the 1 mm gap of
// "thin-gap" seen from 0.94 m (1e-3 relative).
// Far from the origin the rasterised depth itself errs by more: the vertex transform rounds
// world coordinates of size |eye| (viewProj · v in float, ~16 float ulps of |eye| + distance); the
// window adds kSurfaceMatchFarTerm · (|eye| + distance) = 32 · 2^-24 · (|eye| + distance).
inline constexpr double kSurfaceMatchTolerance = 1e-4;
inline constexpr double kSurfaceMatchFarTerm = 32.0 / 16777216.0;

// Per pixel, the true geometric surface: the eye ray through the pixel centre (x + 0.5, y + 0.5,
// as the rasteriser samples) is intersected with the scene, starting just before the rasterised
// distance, so that the triangle the rasteriser kept is found even where a nearer triangle's
// edge passes through the pixel centre.
struct ReferenceSurface {
  uint32_t width = 0, height = 0;
  glm::dvec3 eye{0.0};
  std::vector<SurfaceState> state;
  std::vector<glm::dvec3> position;  // Matched: the hit; Unmatched: worldFromDepth<double>; Sky: 0
  std::vector<glm::dvec3> normal;    // Matched: unit face normal facing the eye; else 0
  uint64_t matched = 0, unmatched = 0;
};
ReferenceSurface referenceSurface(const Bvh& bvh, const std::vector<float>& depth,
                                  const ReconstructionCamera<double>& cam);

// ---- the oracle ---------------------------------------------------------------------------------

// design.md "The oracle": per non-sky pixel the lights that cast shadows, whose range contains the
// point (point, spot), whose outer cone contains it (spot) and that the true geometric normal
// faces (N·L > 0). No culler that is correct can trace fewer rays. Unmatched pixels have no true
// normal: the N·L test is skipped there (their count is an upper bound) and they are counted.
struct OracleRays {
  uint64_t total = 0;
  std::vector<uint32_t> perPixel;
  uint64_t pixelsWithoutNormal = 0;
};
OracleRays oracleRays(const Scene& scene, const ReferenceSurface& surface);
// oracle / traced (1 when nothing was traced). <= 1 for a conservative variant. It can exceed 1
// when a variant drops rays the oracle needs: tile overflow (droppedByOverflow), culling false
// negatives, or a reconstructed normal that wrongly faces away from a light the true normal faces
// (naive normals at depth discontinuities), and on unmatched pixels (see OracleRays).
double rayEfficiency(uint64_t oracle, uint64_t traced);

// ---- accuracy -----------------------------------------------------------------------------------

// Reconstructed normals (GPU, xyzw per pixel, 0 = none) against the reference surface's normals.
struct NormalAccuracy {
  uint64_t compared = 0;               // matched pixels with a reconstructed normal
  uint64_t withoutReconstruction = 0;  // matched pixels where the GPU gave no normal
  uint64_t withoutReference = 0;       // unmatched pixels
  double meanAngleDeg = 0, p95AngleDeg = 0, maxAngleDeg = 0;
  // Mean over compared pixels of the normal images' difference: rgb = n*0.5 + 0.5, per pixel the
  // mean over r, g, b of |rgb_a − rgb_b|, in [0, 1]. This is our reading of the thesis's "mean
  // difference" of Figure 5.3 (0.07975 naive, 0.02264 improved); the thesis does not define it.
  double meanImageDifference = 0;
  std::vector<float> angleDeg;  // per pixel, 0 where not compared
};
NormalAccuracy normalAccuracy(const std::vector<float>& normals, const ReferenceSurface& surface);
nlohmann::json toJson(const NormalAccuracy& acc);

// GPU world positions (xyzw, w = 1 where not sky) against worldFromDepth<double> (Alg. 4.1) and
// worldFromDepthPlain<double> from the same depth values: |p_gpu − p_cpu| / |p_cpu − eye|.
struct PositionAccuracy {
  uint64_t compared = 0;
  double maxRelative = 0, meanRelative = 0;            // against Alg. 4.1 in double
  double maxRelativePlain = 0, meanRelativePlain = 0;  // against the plain inverse in double
  uint64_t nonFinite = 0;                              // GPU positions with NaN/Inf (never compared)
  std::vector<float> relative;                         // per pixel (Alg. 4.1), 0 for sky
};
PositionAccuracy positionAccuracy(const std::vector<float>& positions, const std::vector<float>& depth,
                                  const ReconstructionCamera<double>& cam);
nlohmann::json toJson(const PositionAccuracy& acc);

// ---- CPU shadow reference -----------------------------------------------------------------------

// The GPU shadow pass repeated in double with `bvh`, from the GPU's own positions and normals
// (shaders/shadows_common.glsl.inc): per pixel, per light i of its tile list, the same at-light,
// range/cone (rangeTest), N·L and castShadows decisions, then Bvh::occluded(P, L, tMin, tMax)
// with tMin = gpu::shadowTMin(cameraPos, P) (cameraPos as in FrameConstants: w = 0 gives the
// thesis's constant kShadowTMin, w = kShadowTMinPerMetre the scaled one); then compared with the
// GPU's mask. A mismatching pair is EXPLAINED when float rounding may decide it either way, with δ = kFloatRayShift · (|P| + min(tMax, scene diagonal)):
//  - nearTie: |N·L| or the range/cone margin is within 16 float ulps of its operands (the GPU
//    takes these decisions in float);
//  - endpoint: the CPU answer for [tMin − δ, tMax + δ] differs from [tMin + δ, tMax − δ] (a hit
//    at the ray's ends: t_min self-intersection or geometry at the light);
//  - grazing: the CPU answer changes when the origin moves by δ along ±x, ±y, ±z (the ray passes
//    within δ of a triangle's edge or silhouette).
// δ: lavapipe intersects in float; its edge functions are formed from vertex − origin
// differences and products with relative error a few eps (2^-24) of the magnitudes involved,
// which are bounded by |P| + t; the ray direction itself is normalised in float (another few eps,
// i.e. a displacement of a few eps · t at distance t). 2^-17 = 128 eps leaves a wide margin for
// the accumulated dozens of operations of the traversal and test, and still is 8 µm at 1 m.
inline constexpr double kFloatRayShift = 1.0 / 131072.0;  // 2^-17

struct ShadowComparison {
  std::vector<uint32_t> visibility;  // the CPU's words, laid out as ShadowReadback::visibility
  uint64_t pairs = 0;                // (pixel, light) pairs compared (non-sky × tile count)
  uint64_t rays = 0;                 // pairs where the CPU traced a ray
  uint64_t mismatches = 0;
  uint64_t nearTie = 0, endpoint = 0, grazing = 0;  // explained mismatches, by first reason found
  uint64_t unexplained() const { return mismatches - nearTie - endpoint - grazing; }
  void addCounts(const ShadowComparison& other);  // every count (not visibility)
};
// Preconditions as accountRays; shadows from an analysis frame.
ShadowComparison compareShadows(const Scene& scene, const Bvh& bvh, const ShadowReadback& shadows,
                                const CullingReadback& culling, uint32_t width, uint32_t height,
                                uint32_t tileSize, bool rangeTest, const glm::vec4& cameraPos = glm::vec4(0.0f));

}  // namespace hb
