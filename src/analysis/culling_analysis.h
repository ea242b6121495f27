// Analysis of one frame's GPU light culling (thesis 4.2.3): the CPU reference of the same method
// (cull_ref.h, float: mirrors the GPU), the exact light set of every tile (double), the
// statistics of the GPU result against the exact sets, a lights-per-tile heatmap, and a
// tile-by-tile comparison of the GPU lists with the float reference that tells rounding-level
// disagreements (legitimate: the GPU's float ops differ from the CPU's) from real ones.
//
// Cost: the exact sets test every (tile, light) pair; pairs whose range sphere lies beyond one of
// the tile's planes are rejected cheaply, the rest go through exactLightMeetsTile (GJK for spots).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "base/image_io.h"
#include "config/config.h"
#include "reference/cull_ref.h"
#include "scene/scene.h"

namespace hb {

struct CullingReadback;  // renderer.h

// Everything the GPU culling pass saw. The pointers must outlive every call that takes this.
// Preconditions: depth->size() == width*height (the prepass depth, reverse-Z, 0 = sky);
// view/proj are the float matrices the renderer used (Renderer::view()/proj()); view is rigid;
// tileSize > 0; capacity > 0.
struct CullingInputs {
  const std::vector<float>* depth = nullptr;
  const std::vector<Light>* lights = nullptr;
  glm::mat4 view{1.0f}, proj{1.0f};
  uint32_t width = 0, height = 0;
  // A parameter the config has takes its one default from it (config.h paramDefaults).
  uint32_t tileSize = paramDefaults().tileSize;
  bool aabb = paramDefaults().aabb;
  bool lightCulling = paramDefaults().lightCulling;
  uint32_t capacity = kDefaultTileCapacity;
  uint32_t depthSlices = paramDefaults().depthSlices;  // 0 off, 2..32: the 2.5D slab test (cull_ref.h TileVolume)
};

// Per tile (row-major, tileCount(width) × tileCount(height)), ascending light indices.
struct CullingReference {
  std::vector<TileLightList> same;             // the GPU's method in float, first `capacity` stored
  std::vector<std::vector<uint32_t>> sameAll;  // the same method's full kept set (no capacity)
  std::vector<std::vector<uint32_t>> exact;    // exact (double) light set; empty for sky tiles
  std::vector<std::vector<uint32_t>> needed;   // exact lights reaching one of the tile's pixels
};

// The CPU reference for `in`. Light culling off: every tile keeps every light (as the GPU does,
// sky tiles included); the exact sets do not depend on the flag, nor on depth slices (they are
// the lights meeting the tile's depth-bounded frustum). needed: the lights of the exact set that
// reach, in double, the view-space point of at least one of the tile's non-sky pixels (pixel
// centre, depth as rendered): inside the range ball and, for a spot, its cone; a directional
// light reaches every such point.
CullingReference cullingReference(const CullingInputs& in);

// The GPU readback as per-tile lists (indices sorted ascending, total from the grid).
// Precondition: gpu's tile counts match in's resolution and tile size (HB_ASSERT), each grid
// entry's slice lies inside gpu.indices.
std::vector<TileLightList> gpuTileLists(const CullingInputs& in, const CullingReadback& gpu);

// Statistics of the GPU result against the exact and needed sets (cull_ref.h cullStatistics and
// addGeometryStatistics, sliced when in.depthSlices > 0).
CullStatistics gpuCullStatistics(const CullingInputs& in, const CullingReadback& gpu, const CullingReference& ref);

// Full-resolution lights-per-tile image: every pixel coloured by its tile's `total` through
// heatmapThesis with maxValue = number of lights.
ImageRGBA8 lightsPerTileHeatmap(const CullingInputs& in, const CullingReadback& gpu);

// Keys: tiles, lights_per_tile_mean, lights_per_tile_max, overflow_tiles, false_positive_rate,
// false_positives, false_negatives, dropped_by_overflow, memory_bytes, tile_size, aabb,
// light_culling, depth_slices, needed_pairs, geometry_false_positive_rate (stored lights reaching
// none of the tile's pixels / stored), geometry_false_negatives, sliced_away.
nlohmann::json cullStatisticsJson(const CullStatistics& stats, const CullingInputs& in);

// One light on which the GPU and the float reference disagree in one tile.
struct CullingMismatch {
  uint32_t tile = 0, light = 0;
  bool gpuKept = false;     // true: in the GPU list only; false: in the reference only
  bool borderline = false;  // margin <= bound: float rounding may decide it either way
  double margin = 0.0;      // double-precision distance of the closest comparison to its threshold
  double bound = 0.0;       // the rounding bound it was measured against
};

struct CullingComparison {
  uint64_t hardMismatches = 0;              // must be 0: disagreements rounding cannot explain
  uint64_t borderlineMismatches = 0;        // disagreements within the rounding bound
  uint64_t malformedTiles = 0;              // grid entry inconsistent (offset, count != min(total, cap))
  uint64_t totalMismatchTiles = 0;          // |total - reference total| > borderline lights of the tile
  std::vector<CullingMismatch> mismatches;  // every disagreement, hard and borderline
  bool ok() const { return hardMismatches == 0 && malformedTiles == 0 && totalMismatchTiles == 0; }
};

// Compares the GPU lists with ref.same/ref.sameAll tile by tile (order within a tile ignored).
// A light stored by one side and not the other is a mismatch, except a reference light above the
// last stored GPU index of an overflowing tile (the GPU may have kept it without storing it).
// Each mismatch is borderline when its double margin is within the bound of
// cullingRoundingBound(); otherwise hard. Totals must agree up to the tile's borderline lights.
CullingComparison compareGpuToReference(const CullingInputs& in, const CullingReadback& gpu,
                                        const CullingReference& ref);

// z-binning's own exactness: (pixel, light) pairs where a light of the pixel's tile list reaches the
// pixel's point (pixel centre at its rendered depth, in double: range ball and cone) but lies
// outside the pixel's bin range (ranges: ShadowReadback::ranges). Must be 0: a bin never drops a
// light that reaches a pixel (the bins' ±1 margin, zbin_sort.comp.glsl). Precondition: gpu.lists
// is zbin.
uint64_t zbinMissedPairs(const CullingInputs& in, const CullingReadback& gpu, const std::vector<uint32_t>& ranges);

// Everything above for one frame.
struct CullingAnalysis {
  CullingReference reference;
  CullStatistics stats;
  CullingComparison comparison;
  ImageRGBA8 heatmap;
  nlohmann::json json;  // cullStatisticsJson plus "hard_mismatches" and "borderline_mismatches"
};
CullingAnalysis analyzeCulling(const CullingInputs& in, const CullingReadback& gpu);

// ---- the rounding margin (exposed for tests) ----

// Distance, in double, of the closest comparison the culling test makes for (tile, light) to its
// threshold: |s + r| and |s| for every plane, the cone base point Q, and (with aabb) the sphere-
// AABB distance minus r. Directional lights: +inf (never culled).
double cullingDecisionMargin(const TileVolume<double>& tile, const ViewLight<double>& light, bool aabb);
// The slab test's margin, in metres of view z, for a tile sliced in double (applyDepthSlices):
// the distance of the light's widened z extent's ends to the nearest slab boundary, and of every
// non-sky pixel's z to the two boundaries that enclose the light's slabs (only a pixel crossing
// one of those can change the answer). +inf for a directional light, a flat or unsliced tile.
double sliceDecisionMargin(const TileVolume<double>& tile, const ViewLight<double>& light,
                           const ProjectionParams<double>& proj, const std::vector<float>& depth, uint32_t width,
                           const TileRect& rect);
// The bound float evaluation (CPU or GPU) stays within for those distances (derivation in
// culling_analysis.cpp).
double sliceRoundingBound(const TileVolume<double>& tile, const ViewLight<double>& light);
// The bound on how far float evaluation on CPU or GPU can move those comparisons (derivation in
// culling_analysis.cpp). rays: the tile's corner rays in double; worldPosition: the light's
// world-space position; viewTranslation: |view[3].xyz|.
double cullingRoundingBound(const std::array<glm::dvec3, 4>& rays, const TileVolume<double>& tile,
                            const ViewLight<double>& light, double worldPositionLength, double viewTranslationLength);

}  // namespace hb
