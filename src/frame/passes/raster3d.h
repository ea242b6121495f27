// Primary visibility in compute, the methods of the paper's continuum (Davidovic et al. 2012) other
// than the hardware prepass: per pixel the nearest triangle (id) and its view depth t, in a 64-bit
// visibility buffer (t bits << 32 | id), then its reverse-Z depth copied into the frame's depth
// image, so every later pass reads depth as after the hardware prepass.
//  - "3dr" (raster3d.comp.glsl, raster3d.glsl.inc): brute force over each triangle's screen box:
//    boxes of at most smallArea pixels are rasterized by one thread, larger ones cut into 8x8 tiles
//    that a second dispatch rasterizes a pixel per thread (atomicMin per covered pixel).
//  - "3dr-binned": big boxes binned into the screen's 8x8 tiles (count, scan, fill, a thread per
//    (triangle, tile) item: only tiles the triangle can touch), then one workgroup per screen tile;
//    the result equals "3dr" bit for bit.
//  - "2dr": the paper's baseline, 2D homogeneous edge functions, otherwise as "3dr".
//  - "2dr-binned": "2dr" binned as "3dr-binned", with early-z in the tile pass (the paper's "2DR
//    binning" with its hierarchical w-buffer test).
//  - "3dr-frustum-cull", "3dr-frustum-split", "3dr-full" (raster3d_bvh.comp.glsl): screen frusta
//    traverse a BVH of the scene (primary_bvh.h), culled by frustum (and occlusion), split, and
//    rasterize their leaves' triangles; equal to "3dr" bit for bit.
//  - "raycast" (primary_raycast.*): a ray per pixel along the same camera rays, nearest hit on the
//    frame's TLAS, through ray query where the device has it, else the ray-tracing pipeline.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "config/config.h"
#include "frame/ray_backend.h"
#include "gpu/gpu_timer.h"
#include "gpu/rt_pipeline.h"
#include "gpu/sync.h"
#include "gpu/trace_bvh.h"
#include "gpu/vk_pipeline.h"
#include "gpu/vk_resources.h"
#include "scene/scene.h"
#include "shared/gpu_types.h"

namespace hb {

// The rays of the camera through pixel centres, as the 3DR shader and its CPU reference use them
// (computed in double, rounded once). Perspective: d(x, y) = d0 + x·dx + y·dy, forward component
// 1; the other projections: camera_ray.glsl.inc. `sample`: the position within each pixel the rays
// pass through ((0.5, 0.5) the centre; an anti-aliasing sample, aa_samples.h), perspective and
// orthographic views only.
gpu::Raster3dConstants raster3dConstants(const Camera& camera, uint32_t width, uint32_t height, uint32_t triangleCount,
                                         uint32_t smallArea, uint32_t listPerTile = 64,
                                         glm::vec2 sample = glm::vec2(0.5f));

struct Raster3dCounters {
  uint64_t setups = 0, edgeEvaluations = 0, fallbacks = 0, pixelsTested = 0, covered = 0, atomics = 0, bigTriangles = 0,
           listOverflows = 0, listEntries = 0, binsRefined = 0,
           binsEmpty = 0;  // binned: (triangle, tile) entries tested, of those covering nothing
  // BVH methods (kR3dCounter* in gpu_types.h).
  uint64_t nodesVisited = 0, frusta = 0, frustaSplit = 0, culledFrustum = 0, culledOcclusion = 0, culledEarlyZ = 0,
           stackOverflows = 0;
};

// Entries from one visibility plane to the next: planes start at multiples of 256 B (the largest
// minStorageBufferOffsetAlignment Vulkan allows) for 32-bit entries too, so 64 entries.
inline uint32_t visibilityPlaneStride(uint32_t width, uint32_t height) { return (width * height + 63u) / 64u * 64u; }

// The counters buffer's values (kR3dCounter* order) by name.
Raster3dCounters countersOf(const std::vector<uint64_t>& values);

// The BVH methods' and binned methods' options (r3d_frustum, r3d_min_frustum, r3d_early_z).
struct Raster3dFrustumOptions {
  uint32_t frustum = 256;       // the top frusta's side, a power of two in [8, 256]
  uint32_t minFrustum = 8;      // split down to this side, a power of two in [8, frustum]
  bool earlyZ = false;          // 3dr-binned: early-z in the tile pass (2dr-binned and 3dr-full always)
  uint32_t stackEntries = 768;  // the traversal stack's capacity; tests lower it to reach the fallback
};

// What the BVH of the BVH methods is (render.json "primary").
struct Raster3dBvhStats {
  uint32_t nodes = 0, depth = 0;
  uint64_t bytes = 0;
  double buildMs = 0.0;
};

class Raster3dPass {
 public:
  static constexpr uint32_t kDefaultSmallArea = 64;

  // Precondition: the device has 64-bit buffer atomics and shaderFloat64 (checked: DeviceError);
  // RayCast: rayCast (the frame's ray tracer) has its TLAS. fp64Fallback false only measures what the fallback prevents
  // (holes, double covers).
  Raster3dPass(const VulkanContext& ctx, const Scene& scene, const Camera& camera, uint32_t width, uint32_t height,
               PrimaryMethod mode = PrimaryMethod::Raster3d, uint32_t smallArea = kDefaultSmallArea,
               bool fp64Fallback = true, const RayTracer& rayCast = {}, uint32_t listPerTile = 64,
               const Raster3dFrustumOptions& frusta = {}, AntiAliasing aa = AntiAliasing::None);
  ~Raster3dPass();

  // Makes the resolve write `depth`, a colour R32F storage image (depth_prepass.h
  // kComputeDepthFormat), itself: record() then takes that image and copies nothing. Without it the
  // resolve writes a buffer that record() copies into a D32 image. Call before subPasses().
  void resolveInto(const Image& depth);
  // Rasterizes (or casts) and writes `depth` (by a copy, or directly after resolveInto), declaring each step's accesses
  // through `sync` (the frame's; the readers of the depth and the visibility buffer declare theirs). An analysis frame
  // also counts and adds coverage. With a timer, each dispatch is timed as a sub-pass
  // ("<pass>.triangles", ".count", ".scan", ".fill",
  // ".tiles", ".resolve", and ".depth_copy" unless resolveInto).
  void record(VkCommandBuffer cmd, Sync& sync, const Image& depth, bool analysis, GpuTimer* timer = nullptr) const;
  PrimaryMethod mode() const { return mode_; }
  // The timer entries record() writes inside the pass's own ("raster3d.tiles", ...).
  std::vector<std::string> subPasses() const;
  // What the driver compiled each timed dispatch into (registers, local and shared memory: vk_pipeline.h
  // pipelineStatistics), by sub-pass ("triangles", ..., "resolve"); null where the device does not say.
  nlohmann::json compiled() const;

  // uint64 per pixel, ~0 = nothing: plane 0 the pixel centres (what aa none writes, and what the
  // depth image, shadows and positions use), then with anti-aliasing one plane per stored sample
  // (aa_samples.h), planeStride() entries apart.
  const Buffer& visibility() const { return vis_; }
  uint32_t planes() const { return planes_; }
  // Whether timed frames rasterize every plane in one pass of setup, binning and tiles (3dr-binned,
  // perspective, no early-z: raster3d_common.glsl.inc "Shared sample planes"); analysis frames and
  // the other methods go plane by plane.
  bool sharedPlanes() const { return sharedPlanes_; }
  uint32_t planeStride() const { return planeStride_; }
  // The work list (a count, then uvec2 items): tests seed it with a previous frame's items.
  const Buffer& workList() const { return big_; }
  const Buffer& spans() const { return spans_; }          // a span (id, first item) per big triangle
  const Buffer& constants() const { return constants_; }  // gpu::Raster3dConstants (UBO)
  const Buffer& triangles() const { return triangles_; }  // 3 vec4 per triangle, world space
  uint32_t triangleCount() const { return triangleCount_; }
  uint32_t screenTiles() const { return screenTiles_; }  // 8 x 8-pixel tiles (3dr-binned's bins)

  // Readbacks (after an analysis frame), of plane `plane` (0: the pixel centres).
  std::vector<uint64_t> readVisibility(uint32_t plane = 0) const;
  std::vector<uint32_t> readCoverage(uint32_t plane = 0) const;  // (triangle, pixel) pairs covered, per pixel
  std::vector<uint32_t> readPixelTests(
      uint32_t plane = 0) const;  // triangles tested at each pixel (3 edge evaluations each)
  // The work list (3dr, 3dr-binned, 2dr, 2dr-binned): the items it holds, and after a frame
  // whether a plane asked for more. growList() makes it hold the most any plane of the last frame
  // asked for (rounded up to 64), so that the frame rendered again finds it full nowhere: the same
  // work (and no overflow) on every run; false when it already did, when it cannot grow past what a
  // storage buffer binding may hold (a full list is then handled and counted), or the method has
  // no list.
  // Each frame reads the demand back until one fits (a copy of 8 bytes after the dispatches).
  uint64_t listCapacity() const { return itemCapacity_; }
  bool growList();
  void fixListSize() { listFits_ = true; }               // never grow (tests that need a full list)
  uint64_t listGrownFrom() const { return grownFrom_; }  // the capacity before the first growth (0: never grew)
  Raster3dCounters readCounters() const;                 // plane 0
  Raster3dCounters readSampleCounters() const;           // the sample planes together
  // BVH methods: the hierarchy's size and build time; zeros otherwise.
  const Raster3dBvhStats& bvhStats() const { return bvhStats_; }
  uint32_t frusta() const { return frusta_; }  // BVH methods: workgroups of the traversal

 private:
  void recordRaster(VkCommandBuffer cmd, Sync& sync, bool analysis, GpuTimer* timer) const;
  void recordPlane(VkCommandBuffer cmd, Sync& sync, uint32_t plane, bool analysis, GpuTimer* timer) const;
  void recordRayCast(VkCommandBuffer cmd, Sync& sync, bool analysis) const;
  // The buffers the dispatches read and update (with the analysis frame's counters), each as `a`.
  std::vector<Use> working(Access a, bool analysis) const;
  // The work list and the binned list for `capacity` items, the constants' itemCapacity, and each
  // plane's descriptor set (rasterSets_).
  void makeLists(uint64_t capacity);

  const VulkanContext& ctx_;
  PrimaryMethod mode_;
  uint32_t width_, height_, triangleCount_, tileWorkgroups_ = 0, screenTiles_ = 0, frusta_ = 0;
  uint32_t planes_ = 1, planeStride_ = 0;
  bool sharedPlanes_ = false;
  Buffer planeRays_;  // gpu::R3dPlaneRays (UBO): each plane's d0, sample offset and slack, and the planes' stride
  Buffer constants_, triangles_, vis_, big_, spans_, setups_, counters_, sampleCounters_, coverage_, tested_,
      depthStaging_, bins_, binList_, idBase_, bvhNodes_, bvhOrder_;
  Raster3dBvhStats bvhStats_;
  std::vector<std::unique_ptr<DescriptorSets>> rasterSets_;  // per plane, the dispatches' one set
  std::unique_ptr<ShaderProgram> rasterProgram_;             // the dispatches' shaders, for rasterSets_
  uint64_t itemCapacity_ = 0, grownFrom_ = 0;
  Buffer demandOut_;                   // host-visible: the frame's most items a plane asked for
  mutable bool demandCopied_ = false;  // the last frame copied it (until a frame's list fit)
  bool listFits_ = false;              // a frame found the list big enough: no more copies
  // Per dispatch (brute force: triangles, tiles; binned: triangles, count, scan, fill, tiles) a timed
  // and an analysis pipeline.
  std::vector<std::unique_ptr<Pipeline>> timed_, analysis_;
  Pipeline resolve_;
  std::unique_ptr<Pipeline> resolveImage_;  // resolveInto's: the resolve into depthImage_
  const Image* depthImage_ = nullptr;
  std::unique_ptr<Pipeline> castTimed_, castAnalysis_;                // ray query
  std::unique_ptr<RaygenMissPipeline> castRtTimed_, castRtAnalysis_;  // ray-tracing pipeline
};

}  // namespace hb
