// CPU reference of tiled light culling (thesis 4.2.3). Every step is spelled out so that the GPU
// shader (shaders/culling.glsl.inc) can mirror it op for op: instantiate with T = float to mirror
// the GPU, with T = double for the reference. Conventions (camera.h): view space is right-handed,
// looks down -z; reverse-Z depth is 1 at the near plane and 0 at the far plane; view z of a depth
// value is -D/(depth + C); Vulkan's y points down, which the projection's negative B handles.
//
// Plane convention everywhere: dot(n, p) + d >= 0 inside the tile, n unit length, pointing INTO
// the tile (gpu_types.h TileFrustum stores n in xyz and d in w).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace hb {

constexpr uint32_t kDefaultTileCapacity = 32;  // = gpu::kMaxLightsPerTile (one 32-bit mask)

// A spot whose outer angle exceeds this is culled as its range sphere (a superset of the cone
// ∩ sphere), because tan(θ) → inf at 90°: 89° keeps tan ≤ 57.3, so h*tan θ stays finite in float.
constexpr double kMaxConeCullAngle = 1.5533430342749532;  // 89° in radians

// The A, B, C, D entries of the reverse-Z projection (thesis eq. 4.2): A = P[0][0], B = P[1][1]
// (negative: Vulkan y down), C = P[2][2], D = P[3][2].
template <typename T>
struct ProjectionParams {
  T a, b, c, d;
};
template <typename T>
ProjectionParams<T> projectionParams(const glm::mat<4, 4, T>& proj) {
  return {proj[0][0], proj[1][1], proj[2][2], proj[3][2]};
}

template <typename T>
struct Plane {
  glm::vec<3, T> n;  // unit, into the tile
  T d;
};

// Pixel rectangle of tile (tx, ty): [x0, x1) × [y0, y1), clamped to the image for partial edge
// tiles. Precondition: tx*tileSize < width, ty*tileSize < height.
struct TileRect {
  uint32_t x0, y0, x1, y1;
};
TileRect tileRect(uint32_t tx, uint32_t ty, uint32_t tileSize, uint32_t width, uint32_t height);
uint32_t tileCount(uint32_t pixels, uint32_t tileSize);  // ceil(pixels / tileSize)

// The four tile corners as view-space rays scaled to z = -1 (points on the plane z = -1):
// [0] = (x0, y0) top-left, [1] = (x1, y0) top-right, [2] = (x1, y1) bottom-right,
// [3] = (x0, y1) bottom-left, in pixels. ndc = 2*(px/W) - 1; view = (ndc.x/A, ndc.y/B, -1).
template <typename T>
std::array<glm::vec<3, T>, 4> tileCornerRays(const ProjectionParams<T>& proj, const TileRect& rect, uint32_t width,
                                             uint32_t height);

// The four side planes through the eye (origin) and two corner rays: [0] left = cross(c3, c0),
// [1] top = cross(c0, c1), [2] right = cross(c1, c2), [3] bottom = cross(c2, c3), normalised;
// with A > 0 and B < 0 these normals point into the tile. d = 0 for all four.
template <typename T>
std::array<Plane<T>, 4> tileSidePlanes(const std::array<glm::vec<3, T>, 4>& cornerRays);

// Reverse-Z depth → view-space z (negative in front of the camera): z = -D / (depth + C).
template <typename T>
T viewZFromDepth(T depth, const ProjectionParams<T>& proj);

// Min/max depth over the tile's non-sky pixels. Sky (depth exactly 0: the clear value) is never
// shaded, so it needs no lights and is left out of the range. An all-sky tile returns the
// reductions' identities minDepth = 1, maxDepth = 0, i.e. empty() is maxDepth <= 0.
// Precondition: depth.size() == width*height, row-major, values in [0, 1].
struct TileDepthRange {
  float minDepth = 1.0f;
  float maxDepth = 0.0f;
  bool empty() const { return maxDepth <= 0.0f; }
};
TileDepthRange tileDepthRange(const std::vector<float>& depth, uint32_t width, uint32_t height, const TileRect& rect);

// The tile's depth-bounded frustum: planes [0..3] sides, [4] near (n = (0,0,-1), d = zNear),
// [5] far (n = (0,0,1), d = -zFar); corners [0..3] = cornerRays[i] * -zNear, [4..7] the same at
// zFar; the AABB of those 8 corners. zNear = viewZ(maxDepth) >= zFar = viewZ(minDepth) (reverse-Z:
// the smallest depth is the farthest point). empty: all-sky tile, it receives no light at all.
//
// Depth slices (beyond the thesis; Harada et al., "A 2.5D culling for Forward+", SIGGRAPH Asia
// 2012 Technical Briefs): with slices > 0 (applyDepthSlices) the tile's [zFar, zNear] is cut
// into `slices` equal slabs of view z; depthMask has bit k set when a non-sky pixel lies in slab
// k (k = 0 nearest), and a light is kept only if its z extent meets an occupied slab. slices = 0:
// off (tileVolume's default), and the rest of the test ignores sliceScale and depthMask.
template <typename T>
struct TileVolume {
  std::array<Plane<T>, 6> planes;
  std::array<glm::vec<3, T>, 8> corners;
  glm::vec<3, T> aabbMin, aabbMax;
  T zNear, zFar;
  bool empty;
  uint32_t slices = 0;
  T sliceScale = T(0);  // slices / (zNear - zFar); 0 for a flat tile (zNear == zFar: one slab)
  uint32_t depthMask = 0;
};
template <typename T>
TileVolume<T> tileVolume(const ProjectionParams<T>& proj, const TileRect& rect, uint32_t width, uint32_t height,
                         T minDepth, T maxDepth);

// A light in view space. tanOuter < 0 means "no cone test" (outer angle > kMaxConeCullAngle: the
// spot is culled as its range sphere). cosOuter/sinOuter describe the true cone (exact test).
template <typename T>
struct ViewLight {
  LightType type;
  glm::vec<3, T> position;   // view space
  glm::vec<3, T> direction;  // view space, unit (spot only)
  T range;
  T tanOuter;
  T cosOuter, sinOuter;
  T worldScale;  // |world position| + |view translation|: the size the view transform rounds at
};
// tan(outer) for the cone-vs-plane test, or -1 when outer > kMaxConeCullAngle. What the GPU
// light packer stores in GpuLight::tanOuter.
double spotConeTan(double outerConeAngle);
// Transforms a world-space light by `view` (rigid): position = view*(p,1), direction =
// normalize(mat3(view)*dir); the outer angle is clamped to glTF's [0, pi/2] (float(pi/2) > pi/2).
template <typename T>
ViewLight<T> toViewLight(const Light& light, const glm::mat<4, 4, T>& view);

// Sphere entirely in the negative half-space: dot(n, c) + d < -r.
template <typename T>
bool sphereOutsidePlane(const Plane<T>& plane, const glm::vec<3, T>& centre, T radius);
// Cone (tip, unit axis, height h, base radius rBase) entirely in the negative half-space: both
// the tip and Q, the base point farthest along n, are. Q = tip + h*axis + rBase*v with
// v = normalize(cross(cross(axis, n), axis)) = the unit component of n perpendicular to the axis
// (the vector identity gives n - dot(n, axis)*axis); v = 0 when n ∥ axis (any base point is then
// equally far along n). [Ericson, Real-Time Collision Detection, 5.2.4 / thesis 4.2.3]
template <typename T>
bool coneOutsidePlane(const Plane<T>& plane, const glm::vec<3, T>& tip, const glm::vec<3, T>& axis, T height,
                      T baseRadius);
// Squared distance from the centre to the box <= r².
template <typename T>
bool sphereOverlapsAabb(const glm::vec<3, T>& lo, const glm::vec<3, T>& hi, const glm::vec<3, T>& centre, T radius);

// Thesis 4.2.3 plane tests: point = range sphere vs 6 planes; spot = range sphere AND (if
// tanOuter >= 0) cone of height = range vs 6 planes (the spot's sector lies in both); directional
// always passes.
template <typename T>
bool lightPassesPlanes(const TileVolume<T>& tile, const ViewLight<T>& light);
// Turanzkij's AABB test: range sphere vs the tile frustum's AABB; directional always passes.
template <typename T>
bool lightPassesAabb(const TileVolume<T>& tile, const ViewLight<T>& light);

// ---- depth slices (see TileVolume) ----

// Slab of view-space z: clamp(floor((zNear - z) · sliceScale), 0, slices - 1), clamped in floating
// point before the conversion (a light far outside the tile maps far outside [0, slices)).
// Precondition: tile.slices in 1..32.
template <typename T>
uint32_t sliceOf(const TileVolume<T>& tile, T z);
// Sets tile.slices, tile.sliceScale and tile.depthMask from the tile's non-sky pixels (their view
// z is viewZFromDepth of their depth, in T). Precondition: slices in 2..32 (0 leaves it off);
// depth as tileDepthRange.
template <typename T>
void applyDepthSlices(TileVolume<T>& tile, uint32_t slices, const ProjectionParams<T>& proj,
                      const std::vector<float>& depth, uint32_t width, uint32_t height, const TileRect& rect);
// How far the light's z extent is widened before slicing, so that float rounding never drops a
// light that reaches a pixel: both the pixel's slab and the light's slabs go through the same
// monotone sliceOf (correctly rounded - and *), so only their inputs' errors matter: the pixel's
// z = -D/(d + C) is within 6u·|z| <= 6u·|zFar| (an add, a division of 2.5 ulp on the GPU), and
// the light's view z within 8u·worldScale (culling_analysis.cpp, view transform) plus 2u·(|zc|
// + r) for the two sums zc ± r. Widening by twice their sum, 16u·(|zFar| + |zc| + r +
// worldScale) with u = 2^-24, covers both with room for the widening's own rounding.
template <typename T>
T sliceWidening(const TileVolume<T>& tile, const ViewLight<T>& light);
// Bits sliceOf(zc + r + w) .. sliceOf(zc - r - w) of the light's range sphere (w = sliceWidening;
// a spot's sector lies in its sphere).
template <typename T>
uint32_t lightSliceMask(const TileVolume<T>& tile, const ViewLight<T>& light);

// Kept iff the tile is not empty and the plane test (and, with useAabb, the AABB test, and with
// depth slices, the slab test) keeps it.
template <typename T>
bool lightTouchesTile(const TileVolume<T>& tile, const ViewLight<T>& light, bool useAabb);

// Kept light indices in ascending order: the first `capacity` of them are stored; total counts
// them all, so total > indices.size() flags an overflowing tile.
struct TileLightList {
  std::vector<uint32_t> indices;
  uint32_t total = 0;
};
template <typename T>
TileLightList cullTile(const TileVolume<T>& tile, const std::vector<ViewLight<T>>& lights, bool useAabb,
                       uint32_t capacity = kDefaultTileCapacity);

// ---- exact reference (double) ----

// Euclidean distance from p to the tile's depth-bounded frustum (0 inside). Exact up to rounding:
// outside a convex polyhedron the closest point lies on a face; per face it is the projection of
// p when that lies in the face (inside the other 5 planes), else on one of the 12 edges.
double distanceToTileVolume(const TileVolume<double>& tile, const glm::dvec3& p);
// Does the light's volume meet the tile's volume? Point: the range ball. Spot: the spherical
// sector {|p - tip| <= range, angle(p - tip, axis) <= outer} (exact, via GJK on support functions;
// outer > 90° is not convex and falls back to the ball: conservative). Directional: true unless
// the tile is empty. Conservative at the rounding level: ties and unconverged GJK count as hits.
bool exactLightMeetsTile(const TileVolume<double>& tile, const ViewLight<double>& light);

// ---- statistics ----

// Bytes of the culling data: light grid 16 B per tile + index list 4 B × tiles × capacity
// (so halving the tile size multiplies it by about 4).
uint64_t cullingMemoryBytes(uint32_t width, uint32_t height, uint32_t tileSize, uint32_t capacity);

// kept[i] / exact[i]: tile i's culling result and its exact light set (ascending indices).
// falsePositives: stored lights that do not meet the tile; falsePositiveRate = falsePositives /
// stored pairs (0 when none); falseNegatives: exact lights missing from a tile that did NOT
// overflow; droppedByOverflow: exact lights missing from overflowing tiles; lights per tile
// mean/max are over `total` (lights that passed the test, stored or not).
struct CullStatistics {
  uint64_t tiles = 0;
  uint64_t storedPairs = 0;
  uint64_t exactPairs = 0;
  uint64_t falsePositives = 0;
  double falsePositiveRate = 0.0;
  uint64_t falseNegatives = 0;
  uint64_t droppedByOverflow = 0;
  double meanLightsPerTile = 0.0;
  uint32_t maxLightsPerTile = 0;
  uint64_t overflowTiles = 0;
  uint64_t memoryBytes = 0;
  // Against the geometry (addGeometryStatistics): a light is NEEDED by a tile when it reaches
  // (range ball, and cone for a spot) the view-space point of at least one of its pixels.
  uint64_t neededPairs = 0;
  uint64_t uselessPairs = 0;  // stored lights that reach none of the tile's pixels
  double uselessRate = 0.0;   // uselessPairs / storedPairs (0 when none)
  uint64_t missedNeeded = 0;  // needed lights missing from a tile that did not overflow
  uint64_t slicedAway = 0;    // with depth slices: exact lights the slab test removed
};
// Precondition: kept.size() == exact.size() == tileCount(width)*tileCount(height).
CullStatistics cullStatistics(const std::vector<TileLightList>& kept, const std::vector<std::vector<uint32_t>>& exact,
                              uint32_t width, uint32_t height, uint32_t tileSize, uint32_t capacity);

// Fills the geometry figures of `s` from needed[i], tile i's needed lights (ascending; a subset of
// its exact set). With depth slices the exact set is no longer what a tile must keep (the slab
// test removes lights that meet the frustum between two surfaces on purpose), so `sliced` moves
// the exact lights missing from non-overflowing tiles from falseNegatives to slicedAway and makes
// falseNegatives = missedNeeded: what must be 0 is then "no light that reaches a pixel is lost".
// Precondition: kept.size() == needed.size() == s.tiles, s from cullStatistics on the same kept.
void addGeometryStatistics(CullStatistics& s, const std::vector<TileLightList>& kept,
                           const std::vector<std::vector<uint32_t>>& needed, bool sliced);

}  // namespace hb
