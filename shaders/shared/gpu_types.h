// GPU data structures and constants shared by GLSL and C++. Plain scalar
// and 16-byte-vector members only, laid out for std430/std140 alike; C++ static_asserts the sizes.
#ifndef HB_GPU_TYPES_H
#define HB_GPU_TYPES_H

#ifdef __cplusplus
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
namespace hb::gpu {
using vec2 = glm::vec2;
using vec4 = glm::vec4;
using uvec2 = glm::uvec2;
using uvec4 = glm::uvec4;
using ivec4 = glm::ivec4;
using mat4 = glm::mat4;
using uint = uint32_t;
#define HB_CONST constexpr
#else
#define HB_CONST const
#endif

HB_CONST uint kLightPoint = 0u;
HB_CONST uint kLightSpot = 1u;
HB_CONST uint kLightDirectional = 2u;
HB_CONST uint kMaxLightsPerTile = 32u;  // one 32-bit visibility mask per texel (thesis 4.3.3)

// Shadow pass specialization constants (shadows.*.glsl): normal reconstruction and world positions.
HB_CONST uint kNormalsOff = 0u;
HB_CONST uint kNormalsNaive = 1u;
HB_CONST uint kNormalsImproved = 2u;
HB_CONST uint kNormalsGeometric = 3u;  // the visible triangle's own normal (needs 3D rasterization's ids)
HB_CONST uint kWorldPosAlg41 = 0u;     // thesis Algorithm 4.1
HB_CONST uint kWorldPosMatrix = 1u;    // full inverse view-projection matrix
HB_CONST uint kWorldPosHit = 2u;       // eye + t·d from 3D rasterization's hit (no reconstruction)

// Light lists (config light_lists; frame/passes/light_culling.h). tile: the thesis's per-tile index
// list, capped at kMaxLightsPerTile (one 32-bit visibility word per pixel). bitmask: one bit per
// scene light per tile (ceil(lights/32) words a tile), no cap. zbin: the same masks over the lights
// sorted by view depth, intersected per pixel with its depth bin's [first, last] light range
// (Drobot 2017). Every light list is visited in ascending index (light_walk.glsl.inc), and bit k of
// a pixel's visibility words belongs to the k-th light of its walk.
HB_CONST uint kListTile = 0u;
HB_CONST uint kListBitmask = 1u;
HB_CONST uint kListZbin = 2u;
HB_CONST uint kMaxLights = 4096u;  // light culling's shared visible-set mask; scenes are refused above
HB_CONST uint kZBins = 4096u;      // log-depth bins of z-binning

// Per-pixel ray accounting (analysis frames only), 16-bit counts in one rgba32ui texel:
// x = traced rays | lights the pixel's list walk visited << 16, y = pairs removed by the normal test
// | by the range/cone test << 16, z = lights exactly at the shaded point (no direction, no ray) |
// lights that cast no shadow (visible, no ray) << 16. Each count is <= kMaxLights < 65536.
HB_CONST uint kAccountBits = 16u;
HB_CONST uint kAccountMask = 0xFFFFu;

// Shadow rays (thesis 4.3.3).
HB_CONST float kShadowTMin = 0.001;
// Beyond the thesis (param t_min = "scaled"): t_min = max(kShadowTMin, kShadowTMinPerMetre · |P −
// eye|). A reconstructed position lies within 4u·|P − eye| of the true surface (Alg. 4.1, u =
// 2^-24; shadows_gpu_test), and a shadow ray leaving at N·L = s has risen t·s above the plane at
// t; it cannot hit its own surface when t_min·s > 4u·|P − eye|. With t_min = 400u·|P − eye| that
// holds down to s = 0.01 at every distance; the constant 0.001 m holds it only within
// 0.001 / (400u) = 41.9 m of the eye. Equal to kShadowTMin within those 41.9 m.
HB_CONST float kShadowTMinPerMetre = 400.0 * 5.9604644775390625e-8;
HB_CONST float kDirectionalTMax = 1000.0;

// Camera and frame constants (uniform buffer).
struct FrameConstants {
  mat4 view;
  mat4 viewInv;
  mat4 proj;
  mat4 viewProj;
  mat4 viewProjInv;
  vec4 cameraPos;  // xyz world, w = shadow t_min per metre of distance to the eye (0: constant)
  vec4 extent;     // x = width, y = height, z = 1/width, w = 1/height
  uint tileCountX;
  uint tileCountY;
  uint tileSize;
  uint lightCount;
  vec4 ambient;  // rgb: the ambient term's radiance (color·intensity) where ambient occlusion runs; w = 1 then, else 0
  // Light lists: x = kList*, y = mask words per tile (bitmask, zbin: ceil(lightCount / 32)),
  // z = visibility words per pixel (tile: 1; else y), w = where the z-bins begin in the list buffer.
  uvec4 lists;
  // z-bins: x = the near view distance of bin 0, y = kZBins / log2(far / near) (zbinOf).
  vec4 zbins;
};

// A shadow ray's t_min at world position p: kShadowTMin when cameraPos.w is 0 (the thesis), else
// max(kShadowTMin, cameraPos.w · |p − eye|) (see kShadowTMinPerMetre). One body per language, so
// the CPU ray analysis and both GPU backends agree.
#ifdef __cplusplus
inline float shadowTMin(const glm::vec4& cameraPos, const glm::vec3& p) {
  return glm::max(kShadowTMin, cameraPos.w * glm::length(p - glm::vec3(cameraPos)));
}
#else
float shadowTMin(vec4 cameraPos, vec3 p) { return max(kShadowTMin, cameraPos.w * length(p - cameraPos.xyz)); }
#endif

// The z-bin of view distance d (> 0 in front of the eye): log-spaced from zbins.x, clamped to
// [0, kZBins − 1]. One body per language (light_culling.h derives the ±1 bin margin it is used with).
#ifdef __cplusplus
inline uint zbinOf(float d, const glm::vec4& zbins) {
  const float u = std::log2(std::max(d, zbins.x) / zbins.x) * zbins.y;
  return uint(std::min(u, float(kZBins - 1u)));
}
#else
uint zbinOf(float d, vec4 zbins) {
  float u = log2(max(d, zbins.x) / zbins.x) * zbins.y;
  return uint(min(u, float(kZBins - 1u)));
}
#endif

// One punctual light in world space. positionRange.w = range; directionCos.w = cos(outer cone).
struct GpuLight {
  vec4 positionRange;
  vec4 directionCosOuter;  // xyz unit direction the light points, w = cos(outer)
  vec4 colorIntensity;     // rgb linear colour, a = intensity
  uint type;
  float cosInner;
  uint castShadows;
  float tanOuter;  // tan(outer cone angle), for the cone-vs-plane test
};

// A light in view space, computed once per frame for light culling (light_view.comp.glsl; the
// C++ mirror's ViewLight<float>): every tile tests these instead of transforming every light.
struct GpuViewLight {
  vec4 positionRange;  // xyz view-space position, w range
  vec4 directionTan;   // xyz unit view-space direction, w tanOuter (spot: < 0 = no cone test)
  float worldScale;    // |world position| + |view translation| (the 2.5D slab test's widening)
  uint type;
  uint pad0, pad1;
};

// Four side planes of a tile's frustum in view space: xyz = unit normal pointing into the tile,
// w = distance (plane: dot(n, p) + w = 0; eye at origin so w = 0).
struct TileFrustum {
  vec4 planes[4];
};

// Light grid entry: the tile's slice of the light index list.
struct LightGridEntry {
  uint offset;
  uint count;  // lights stored (<= capacity)
  uint total;  // lights that touched the tile (> count: the tile overflowed)
  uint pad;
};

// A glTF metallic-roughness material (shading pass). Texture indices index the bindless array;
// -1 = none (use the factors alone).
struct GpuMaterial {
  vec4 baseColorFactor;
  float metallicFactor;
  float roughnessFactor;
  int baseColorTexture;
  int metallicRoughnessTexture;
};

// Push constants of the raster passes: one draw item.
struct DrawConstants {
  mat4 modelViewProj;
  mat4 model;
  uint material;
  uint firstIndex;    // of the draw's first index in the scene's index buffer
  uint vertexOffset;  // added to each index
  uint triangleBase;  // global id of the draw's first triangle (3D rasterization's triangle ids)
};

// One draw item for the visibility-buffer shading pass (shading_visbuffer.comp.glsl): what the
// raster passes push per draw, as a buffer indexed by the draw a triangle belongs to.
struct GpuDraw {
  mat4 model;
  mat4 normalMatrix;  // transpose(inverse(mat3(model))) as the forward vertex shader computes it
  uint material;
  uint firstIndex;
  uint vertexOffset;
  uint triangleBase;
};

// 3D rasterization (Davidovic et al. 2012; frame/passes/raster3d.h). Rays from the eye through
// pixel centres: d(x, y) = rayD0 + x·rayDx + y·rayDy for pixel indices x, y, with d's component
// along the camera's forward axis 1, so a hit's ray parameter t is its view depth.
struct Raster3dConstants {
  vec4 rayD0;    // xyz: world direction through the centre of pixel (0, 0)
  vec4 rayDx;    // xyz: its step per pixel in x
  vec4 rayDy;    // xyz: its step per pixel in y (down)
  vec4 eye;      // xyz: world eye; vertices are made eye-relative in float before setup
  vec4 forward;  // xyz: unit view direction (view -z) in world space
  vec4 right;    // xyz: unit view +x in world space
  vec4 up;       // xyz: unit view +y in world space
  vec4 depth;    // x znear, y zfar, z C, w D: reverse-Z depth = D / t - C (orthographic: D - C·t; camera.h)
  vec4 project;  // x W/(2·a·tan(fov/2)), y H/(2·tan(fov/2)), z W/2 - 0.5, w H/2 - 0.5
  uint width;
  uint height;
  uint triangleCount;
  uint smallArea;       // screen boxes of at most this many pixels are rasterized by their own thread
  uint itemCapacity;    // brute force: (triangle, 8x8 tile of its box) work items the list holds;
                        // binned: (triangle, screen tile) entries
  uint tileWorkgroups;  // workgroups of the tile dispatch (each strides over the items)
  uint projection;      // kProjection*: the camera's projection (camera_ray.glsl.inc)
  float boxMargin;      // perspective: how far (px) a float ray's pixel may lie from where the
                        // constants project its points (raster3dConstants derives it; r3dScreenBox)
  // Orthographic: ray origins eye + origin0 + x·originX + y·originY (xyz), direction forward.
  vec4 origin0;
  vec4 originX;
  vec4 originY;
  // Paraboloid: x cx, y cy (pixel indices of the disk's centre), z 1/R (R its radius in pixels).
  // Latlong: x 2π/W, y π/H (radians per pixel).
  vec4 view;
};

// A node of primary visibility's BVH (gpu/primary_bvh.h), 48 bytes.
struct PrimaryBvhNode {
  vec4 lo;     // xyz: the box's min corner (world)
  vec4 hi;     // xyz: its max corner
  uvec4 info;  // x: right child (0: a leaf; the left child is this node + 1), y: first entry of the
               // triangle order its subtree occupies, z: how many, w: unused
};

// A big triangle's setup (3dr-binned, 2dr-binned: raster3d_common.glsl.inc), written once by the
// per-triangle pass at its span's index and read by the count, fill and tile passes, which before
// set the triangle up again for each of its tiles. The fields of R3dSetup and its screen box.
struct R3dSetupRecord {
  ivec4 box;         // lo.x, lo.y, hi.x, hi.y (pixels, inclusive)
  vec4 rowA;         // w: planeOffset
  vec4 rowB;         // w: volume
  vec4 rowC;         // w: orientation
  vec4 errA;         // w: the nearest vertex's view depth less its rounding margin (the tile pass's early-z)
  vec4 errB;         // w: shared sample planes (R3dPlaneRays), the largest rowA over the planes, x
  vec4 errC;         // w: ... y
  vec4 planeNormal;  // w: ... z
  vec4 p0;           // w: shared sample planes, the smallest rowA over the planes, x
  vec4 p1;           // w: ... y
  vec4 p2;           // w: ... z
  uvec4 info;        // x: the triangle id; yzw: shared sample planes, the largest errA over the planes (float bits)
};

// 3dr-binned anti-aliasing with shared sample planes (raster3d_tiles.comp.glsl): one pass of setup,
// binning and tiles for the centre and every stored sample. Plane p's rays start at d0[p] (its
// Raster3dConstants' rayD0; plane 0 the centre's); rayDx and rayDy are every plane's. The tile pass
// tests plane p's coverage with the centre's rows at (x + offset[p].x, y + offset[p].y): d0[p] is
// d0[0] + offset.x·rayDx + offset.y·rayDy but for the rounding of each to float, at most `slack`
// (per component, over the planes) apart.
HB_CONST uint kR3dMaxPlanes = 17u;  // the centre and at most 16 stored samples
struct R3dPlaneRays {
  vec4 d0[kR3dMaxPlanes];
  vec4 offset[kR3dMaxPlanes];  // xy: the sample's position in its pixel less the centre's, px
  uvec4 info;                  // x: visibility entries between planes (Raster3dPass::planeStride)
  vec4 slack;                  // xyz: the largest |d0[p] − (d0[0] + offset.x·rayDx + offset.y·rayDy)|
};

HB_CONST uint kProjectionPerspective = 0u;
HB_CONST uint kProjectionOrthographic = 1u;
HB_CONST uint kProjectionParaboloid = 2u;
HB_CONST uint kProjectionLatlong = 3u;

// Counters of an analysis frame of the 3DR pass (never written in timed frames).
HB_CONST uint kR3dCounterSetups = 0u;            // triangles set up (not culled before setup)
HB_CONST uint kR3dCounterEdgeEvals = 1u;         // edge-function evaluations (3 per pixel tested)
HB_CONST uint kR3dCounterFallbacks = 2u;         // of those, re-evaluated in double
HB_CONST uint kR3dCounterPixelsTested = 3u;      // pixels tested (in screen boxes)
HB_CONST uint kR3dCounterCovered = 4u;           // (triangle, pixel) pairs covered, depth-tested or not
HB_CONST uint kR3dCounterAtomics = 5u;           // atomicMin calls (covered pairs within [znear, zfar])
HB_CONST uint kR3dCounterBig = 6u;               // triangles whose box went to the tile pass
HB_CONST uint kR3dCounterOverflow = 7u;          // of those, rasterized by their own thread (list full)
HB_CONST uint kR3dCounterListEntries = 8u;       // binned: (triangle, screen tile) entries the frame needs
HB_CONST uint kR3dCounterBinsRefined = 9u;       // binned: (triangle, screen tile) entries the tile pass tested
HB_CONST uint kR3dCounterBinsEmpty = 10u;        // of those, entries that covered no pixel of the tile
HB_CONST uint kR3dCounterNodes = 11u;            // BVH methods: (node, frustum) pairs tested
HB_CONST uint kR3dCounterFrusta = 12u;           // BVH methods: top-level frusta (r3d_frustum px a side)
HB_CONST uint kR3dCounterSplits = 13u;           // BVH methods: (node, frustum) pairs split into 4 (Fig. 6b, c)
HB_CONST uint kR3dCounterCulledFrustum = 14u;    // BVH methods: triangles of nodes outside their frustum
HB_CONST uint kR3dCounterCulledOcclusion = 15u;  // BVH methods: triangles of nodes behind the depth
HB_CONST uint kR3dCounterCulledEarlyZ = 16u;     // (triangle, 8x8 block) pairs skipped by early-z
HB_CONST uint kR3dCounterStackOverflows = 17u;   // BVH methods: nodes rasterized whole (stack full)
HB_CONST uint kR3dCounterCount = 18u;

// One layered depth map (Aalund et al. 2015; reference/ldm_ref.h defines the view): an
// orthographic view along dir over the scene's bounding sphere (centre, radius). Pixel (i, j) of an
// R×R map is the line through centre + (2(i + ½)/R − 1)·radius·right + (1 − 2(j + ½)/R)·radius·up
// along dir; a point's depth is z = dot(p − centre, dir) + radius, in [0, 2·radius].
struct LdmMap {
  vec4 dir;           // xyz unit
  vec4 right;         // xyz unit
  vec4 up;            // xyz unit
  vec4 centreRadius;  // xyz centre, w radius
};

// The lists (ldm_build.frag.glsl, ldm_list = max64): every link is a 64-bit record
// (key << 32) | node, node >= 1, 0 = the end. key = kLdmKeyTop − floatBits(z) for z >= 0, so a
// larger record is a nearer entry along dir and lists kept in descending records are sorted by
// ascending z. links[pixel] heads pixel's list; links[pixels + node − 1] is node's next link.
// The links are read and written through their buffer device address (N·R² heads and a node per
// fragment outgrow lavapipe's 128 MiB storage binding at N = 128, R = 256 already).
HB_CONST uint kLdmKeyTop = 0xFFFFFFFFu;
HB_CONST uint kLdmMaxInsertSteps = 4096u;  // a bounded insertion; longer ones are counted, not hung
HB_CONST uint kLdmCounterAllocated = 0u;   // nodes asked for (over capacity ones included)
HB_CONST uint kLdmCounterOverflow = 1u;    // fragments dropped: the node pool was full
HB_CONST uint kLdmCounterUnfinished = 2u;  // insertions cut at kLdmMaxInsertSteps
HB_CONST uint kLdmCounterCasRetries = 3u;  // cas: compare-and-swaps that lost to another insertion
HB_CONST uint kLdmCounterFp64 = 4u;        // 3dr build: edge values decided in double
// 3dr build: a (triangle, map) pair whose pixel box holds more than kLdmSmallBox centres is not
// rasterized by its own thread but split into chunks of kLdmChunk pixels of its box in row order,
// each a workgroup's (one pixel a thread), listed in the chunk list (Chunks: uvec2 (triangle,
// map | chunk << 11); maps <= 2048, and a box of at most 4096² pixels has at most 2^18 chunks).
HB_CONST uint kLdmCounterChunks = 5u;         // chunk entries the insert / count phase asked for
HB_CONST uint kLdmCounterChunksFill = 6u;     // the same for the fill phase (sbuffer)
HB_CONST uint kLdmCounterChunkOverflow = 7u;  // large pairs rasterized by their own thread: the chunk list was full
HB_CONST uint kLdmCounterCount = 8u;
HB_CONST uint kLdmSmallBox = 64u;  // pixel centres in a pair's box up to which its own thread rasterizes it
HB_CONST uint kLdmChunk = 512u;    // pixels of a large pair's box a chunk holds (a workgroup of 64's)
// The list layouts (ldm_insert.glsl.inc), in the links buffer at its device address:
//   max64: uint64 links[maps·R² heads + capacity next links] as above.
//   cas:   uint words[maps·R² heads | capacity next nodes | capacity depths (float bits)]; a head or
//          next of 0 ends the list, node n (>= 1) has next words[heads + n − 1] and depth
//          words[heads + capacity + n − 1]; lists ascending in depth.
//   sbuffer: uint words[pixels + 1 offsets | pixels cursors | capacity depths | capacity triangle
//          ids]: a count pass counts each pixel's fragments into its offset word, an exclusive scan
//          turns the counts into offsets (words[pixels] = the total), a fill pass writes each
//          fragment at offset + a per-pixel cursor, and a per-pixel sort orders each range by (depth,
//          triangle id): exact allocation and the same words whatever the arrival order.
HB_CONST uint kLdmListMax64 = 0u;
HB_CONST uint kLdmListCas = 1u;
HB_CONST uint kLdmListSbuffer = 2u;
HB_CONST uint kLdmPhaseInsert = 0u;  // max64, cas: one pass
HB_CONST uint kLdmPhaseCount = 1u;   // sbuffer: count
HB_CONST uint kLdmPhaseFill = 2u;    // sbuffer: fill (after the scan)

// Ambient occlusion (ao_common.glsl.inc; effects/ambient_occlusion/ao_effect.h).
HB_CONST uint kAoLdm = 0u;          // trace the LDMs along the N directions
HB_CONST uint kAoRayTraced = 1u;    // ray trace the same N directions
HB_CONST uint kAoReference = 2u;    // cosine-weighted Monte Carlo, `samples` stratified rays
HB_CONST uint kAoHbao = 3u;         // screen space: horizon-based AO from the depth buffer
HB_CONST uint kAoGtao = 4u;         // screen space: ground-truth-based AO (XeGTAO's slices)
HB_CONST float kAoSky = -1.0;       // an AO value: the pixel sees the sky (no surface)
HB_CONST float kAoNoNormal = -2.0;  // an AO value: no normal could be reconstructed (not shaded by AO)
struct AoConstants {
  uint directions;           // N
  uint resolution;           // R: each LDM is R×R
  uint mapPixels;            // N·R²: where the next links begin in the LDM links buffer
  uint samples;              // reference rays per pixel (a square)
  float dMax;                // obscurance distance; 0: none (occlusion)
  float biasScale;           // scale of the derived LDM bias (ao_common.glsl.inc)
  uint maxListSteps;         // a bounded walk of a pixel's list (the node pool)
  uint samplesSide;          // √samples
  uvec2 ldmLinks;            // the LDM links buffer's device address (lo, hi): it outgrows a binding
  uint ldmList;              // kLdmList*
  uint ldmCapacity;          // the node pool (cas: where the depths begin after the next links)
  uint hbaoSteps;            // hbao: samples per screen direction; gtao: per side of a slice
  float hbaoRadius;          // hbao, gtao: the world radius of the kernel (d_max, or the scene's bounding radius)
  uint envWidth, envHeight;  // environment light (RADIANCE = 1): the map's size (1 x 1: a uniform colour)
  vec4 envScale;             // rgb: color·intensity (scene.h Environment)
  vec4 envRotation;          // cos, sin of the rotation about +y; zw unused
};

// Single-bounce indirect light (indirect_common.glsl.inc; effects/indirect/indirect_effect.h).
HB_CONST uint kFootprintRotated = 0u;   // the incoming directional differentials rotated d1 -> d2 (the paper's)
HB_CONST uint kFootprintCell = 1u;      // differentials spanning the split direction's share of the sphere
HB_CONST uint kIndirectLdm = 0u;        // split photons traced through the LDMs
HB_CONST uint kIndirectRayTraced = 1u;  // the same photons traced by the ray tracer
HB_CONST uint kIndirectReference = 2u;  // gathered: cosine-weighted rays to lit surfaces
// A photon slot's status (Photon.normalStatus.w as uint bits). Every slot is written every frame.
HB_CONST uint kPhotonEmpty = 0u;    // no flux: the primary photon missed, or the direction lies in the surface
HB_CONST uint kPhotonStored = 1u;   // splatted
HB_CONST uint kPhotonHidden = 2u;   // landed where the camera does not see it (discarded, flux counted)
HB_CONST uint kPhotonEscaped = 3u;  // the split ray met nothing (left the scene)
HB_CONST uint kPhotonGrazing = 4u;  // arrived within 1e-3 of its surface's plane: no bounded footprint
// One split photon in its fixed slot (primary · N + direction): position, flux (rgb, W) and the
// positional differentials at its landing point, the landing surface's normal (facing the camera).
struct Photon {
  vec4 positionFluxR;
  vec4 duFluxG;
  vec4 dvFluxB;
  vec4 normalStatus;
};
// An emitting image plane at unit distance from a light (reference/photon_ref.h PhotonFace):
// side×side texels over [-halfExtent, halfExtent]², each texel one primary photon.
struct PhotonFace {
  vec4 forwardHalfExtent;  // xyz unit forward, w halfExtent
  vec4 right;              // xyz unit
  vec4 up;                 // xyz unit
  uint light;              // index into the lights buffer
  uint firstPrimary;       // face f's texels are primaries firstPrimary .. + side² − 1
  uint pad0, pad1;
};
// The compute splat (splat=compute): a slot chunk, a coarse bin's side and a gather tile's side.
HB_CONST uint kSplatChunk = 65536u;  // slots a binning workgroup scans (256 rounds of 256)
HB_CONST uint kSplatBin = 128u;      // pixels: a coarse bin's side by default (splat_bin), a multiple of the tile's
HB_CONST uint kSplatTile = 16u;      // pixels: one 256-thread workgroup gathers a tile
HB_CONST uint kSplatBinRow = 8u;     // the most bins of a row a binning workgroup counts and fills
// The compute splat's push constants (photon_splat_bin.comp.glsl, photon_splat.comp.glsl).
struct SplatConstants {
  uint slots;      // photon slots
  uint chunks;     // slot chunks of kSplatChunk
  uint binsX;      // coarse bins of binPixels across
  uint binsY;      // and down
  uint capacity;   // the list's entries
  uint tilesX;     // gather tiles of kSplatTile pixels across
  uint tilesY;     // and down
  uint binPixels;  // a coarse bin's side (effects.indirect.splat_bin)
  uint first;      // the first slot this run splats (slots: how many from it)
  uint workBase;   // analysis frames: the run's first tile in the gather's work counts (SplatWork)
  uint rowBins;    // bins of a row a count or fill group takes (1, 2, 4 or kSplatBinRow)
  uint pad0;
};
struct IndirectConstants {
  uint directions;        // N
  uint resolution;        // R of the LDMs
  uint mapPixels;         // N·R²
  uint ldmList;           // kLdmList*
  uint ldmCapacity;       // the node pool
  uint maxListSteps;      // a bounded walk of a pixel's list
  float biasScale;        // scale of the derived LDM bias (ldm_trace.glsl.inc)
  uint side;              // primary photons per face side
  uvec2 ldmLinks;         // the LDM links buffer's device address (lo, hi)
  uint primaries;         // primary photons in all
  uint samples;           // reference: rays per pixel (a square)
  uint samplesSide;       // √samples
  uint faces;             // PhotonFace entries
  float ldmPixel;         // 2r/R: an LDM pixel's side (m), for the landing test's tolerance
  float maxAnisotropy;    // a stored footprint's longest axis over its shortest at most this (0: off)
  uint bounces;           // K: diffuse bounces (indirect_common.glsl.inc bounceTrace; reference: path length)
  uint bounceDirections;  // M: the directions at the second bounce, halving at each further one
  uint footprint;         // kFootprint*: the split photons' directional differentials
  uint pad1;
};

#ifdef __cplusplus
static_assert(sizeof(AoConstants) == 96, "AoConstants layout");
static_assert(sizeof(LdmMap) == 64, "LdmMap layout");
static_assert(sizeof(Photon) == 64, "Photon layout");
static_assert(sizeof(PhotonFace) == 64, "PhotonFace layout");
static_assert(sizeof(IndirectConstants) == 80, "IndirectConstants layout");
static_assert(sizeof(SplatConstants) == 48, "SplatConstants layout");
static_assert(sizeof(GpuMaterial) == 32, "GpuMaterial layout");
static_assert(sizeof(DrawConstants) == 144, "DrawConstants layout");
static_assert(sizeof(Raster3dConstants) == 9 * 16 + 32 + 4 * 16, "Raster3dConstants layout");
static_assert(sizeof(PrimaryBvhNode) == 48, "PrimaryBvhNode layout");
static_assert(sizeof(R3dSetupRecord) == 12 * 16, "R3dSetupRecord layout");
static_assert(sizeof(R3dPlaneRays) == (2 * kR3dMaxPlanes + 2) * 16, "R3dPlaneRays layout");
static_assert(sizeof(GpuDraw) == 2 * 64 + 16, "GpuDraw layout");
static_assert(sizeof(FrameConstants) == 5 * 64 + 3 * 16 + 16 + 2 * 16, "FrameConstants layout");
static_assert(sizeof(GpuLight) == 64, "GpuLight layout");
static_assert(sizeof(GpuViewLight) == 48, "GpuViewLight layout");
static_assert(sizeof(TileFrustum) == 64, "TileFrustum layout");
static_assert(sizeof(LightGridEntry) == 16, "LightGridEntry layout");
}  // namespace hb::gpu
#endif

#endif
