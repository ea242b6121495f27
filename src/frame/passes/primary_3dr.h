// Primary visibility by 3D rasterization in compute (Davidovic et al. 2012; shaders
// raster3d.comp.glsl, raster3d.glsl.inc): per pixel the nearest triangle (id) and its view depth t,
// in a 64-bit visibility buffer (t bits << 32 | id, atomicMin), then its reverse-Z depth copied into
// the frame's depth image, so every later pass reads depth as after the hardware prepass.
// Brute force over each triangle's screen box ("3dr"): boxes of at most smallArea pixels are
// rasterized by one thread, larger ones cut into 8x8 tiles that a second dispatch rasterizes a
// pixel per thread. Binned ("3dr-binned"): of a larger box only the tiles the triangle can touch
// (its edge functions at the tile's corners); the result is the same bit for bit.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "gpu/vk_pipeline.h"
#include "gpu/vk_resources.h"
#include "scene/scene.h"
#include "shared/gpu_types.h"

namespace hb {

// The rays of a pinhole camera through pixel centres, as the 3DR shader and its CPU reference use
// them (computed in double, rounded once): d(x, y) = d0 + x·dx + y·dy, forward component 1.
gpu::Raster3dConstants raster3dConstants(const Camera& camera, uint32_t width, uint32_t height,
                                         uint32_t triangleCount, uint32_t smallArea);

struct Raster3dCounters {
  uint64_t setups = 0, edgeEvaluations = 0, fallbacks = 0, pixelsTested = 0, covered = 0, atomics = 0,
           bigTriangles = 0, listOverflows = 0;
};

class Raster3dPass {
 public:
  static constexpr uint32_t kDefaultSmallArea = 64;

  // Precondition: the device has 64-bit buffer atomics and shaderFloat64 (checked: DeviceError).
  // fp64Fallback false only measures what the fallback prevents (holes, double covers).
  Raster3dPass(const VulkanContext& ctx, const Scene& scene, const Camera& camera, uint32_t width, uint32_t height,
               uint32_t smallArea = kDefaultSmallArea, bool fp64Fallback = true, bool binned = false);
  ~Raster3dPass();

  // Rasterizes and writes `depth` (left in DEPTH_READ_ONLY_OPTIMAL, readable by compute, ray
  // tracing, fragment tests and copies). An analysis frame also counts and adds coverage.
  void record(VkCommandBuffer cmd, const Image& depth, bool analysis) const;

  const Buffer& visibility() const { return vis_; }  // uint64 per pixel, ~0 = nothing
  const Buffer& constants() const { return constants_; }  // gpu::Raster3dConstants (UBO)
  const Buffer& triangles() const { return triangles_; }  // 3 vec4 per triangle, world space
  uint32_t triangleCount() const { return triangleCount_; }

  // Readbacks (after an analysis frame).
  std::vector<uint64_t> readVisibility() const;
  std::vector<uint32_t> readCoverage() const;  // (triangle, pixel) pairs covered, per pixel
  std::vector<uint32_t> readPixelTests() const;  // triangles tested at each pixel (3 edge evaluations each)
  Raster3dCounters readCounters() const;

 private:
  const VulkanContext& ctx_;
  uint32_t width_, height_, triangleCount_, tileWorkgroups_ = 0;
  Buffer constants_, triangles_, vis_, big_, counters_, coverage_, tested_, depthStaging_;
  DescriptorSets rasterSets_, resolveSets_;
  Pipeline smallTimed_, smallAnalysis_, bigTimed_, bigAnalysis_, resolve_;
};

}  // namespace hb
