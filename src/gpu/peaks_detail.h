// What peaks.cpp's microbenchmarks and peaks_rays.cpp's ray rates share: the sizes of one
// repetition by device kind, and the timing of repetitions. Internal to gpu/peaks*.cpp.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/peaks.h"

namespace hb::peaks_detail {

// What one repetition of each microbenchmark does, by device kind. A GPU's buffers are far larger
// than its last-level cache (H100: 50 MiB) so that bandwidth is DRAM's; a CPU device's are small
// enough to keep the whole measurement near a second on lavapipe.
struct Sizes {
  uint32_t bufferBytes;    // read, write, copy: each buffer
  uint32_t atomics;        // atomic operations a repetition
  uint32_t fmaThreads;     // FMA threads ...
  uint32_t fmaIterations;  // ... of 8 FMAs an iteration each
  uint32_t target;         // the raster target is target x target pixels
  uint32_t cells;          // triangle rate: cells x cells 1-pixel cells (two triangles each)
  uint32_t fillLayers;     // fill rate: screen-sized quads drawn this many times
  int warmup, repetitions;
};

Sizes sizesFor(const DeviceInfo& d);
double median(std::vector<double> v);
std::vector<double> timeRepetitions(const VulkanContext& ctx, const Sizes& sizes,
                                    const std::function<void(VkCommandBuffer)>& record);
Peak makePeak(std::string key, std::string unit, double work, std::vector<double> ms, std::string description);

}  // namespace hb::peaks_detail
