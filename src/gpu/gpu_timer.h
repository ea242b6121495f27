// Per-pass GPU timestamps. A frame writes a begin/end timestamp pair per pass into a query pool;
// results are read after the frame's fence, masked to timestampValidBits and scaled by
// timestampPeriod (ns per tick) to milliseconds.
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "gpu/vk_context.h"

namespace hb {

class GpuTimer {
 public:
  // maxPasses: the most begin/end pairs per frame (plus one pair for the whole frame).
  GpuTimer(const VulkanContext& ctx, uint32_t maxPasses);
  ~GpuTimer();
  GpuTimer(const GpuTimer&) = delete;

  bool available() const { return available_; }
  void reset(VkCommandBuffer cmd);       // before the frame's first pass
  void frameBegin(VkCommandBuffer cmd);  // top of the frame
  void frameEnd(VkCommandBuffer cmd);    // bottom of the frame
  // Intervals nest: end() closes the latest open begin(), so a pass can time its dispatches as
  // sub-passes inside its own interval ("raster3d" contains "raster3d.tiles").
  void begin(VkCommandBuffer cmd, const std::string& pass);
  void end(VkCommandBuffer cmd);
  // Milliseconds per pass in the order recorded, and the frame's total (first begin → last end).
  std::vector<std::pair<std::string, double>> read(double* frameMs) const;

 private:
  const VulkanContext& ctx_;
  VkQueryPool pool_ = VK_NULL_HANDLE;
  uint32_t capacity_ = 0;
  uint32_t next_ = 0;
  std::vector<std::string> names_;
  std::vector<uint32_t> open_;  // query index of each open interval's begin
  bool available_ = false;
  uint64_t mask_ = ~0ull;
  double periodNs_ = 1.0;
};

}  // namespace hb
