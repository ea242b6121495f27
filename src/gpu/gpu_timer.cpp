#include "gpu/gpu_timer.h"

#include "base/errors.h"

namespace hb {

GpuTimer::GpuTimer(const VulkanContext& ctx, uint32_t maxPasses) : ctx_(ctx) {
  const DeviceInfo& info = ctx.info();
  available_ = info.timestampValidBits > 0 && info.timestampPeriodNs > 0;
  if (!available_) return;
  capacity_ = 2 * (maxPasses + 1);
  mask_ = info.timestampValidBits >= 64 ? ~0ull : ((1ull << info.timestampValidBits) - 1);
  periodNs_ = info.timestampPeriodNs;
  VkQueryPoolCreateInfo qi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  qi.queryType = VK_QUERY_TYPE_TIMESTAMP;
  qi.queryCount = capacity_;
  VK_CHECK(vkCreateQueryPool(ctx.device(), &qi, nullptr, &pool_));
}

GpuTimer::~GpuTimer() {
  if (pool_) vkDestroyQueryPool(ctx_.device(), pool_, nullptr);
}

void GpuTimer::reset(VkCommandBuffer cmd) {
  next_ = 2;  // 0/1 are the frame pair
  names_.clear();
  open_.clear();
  if (available_) vkCmdResetQueryPool(cmd, pool_, 0, capacity_);
}

void GpuTimer::frameBegin(VkCommandBuffer cmd) {
  if (available_) vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT, pool_, 0);
}
void GpuTimer::frameEnd(VkCommandBuffer cmd) {
  if (available_) vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT, pool_, 1);
}

void GpuTimer::begin(VkCommandBuffer cmd, const std::string& pass) {
  if (!available_) return;
  HB_ASSERT(next_ + 2 <= capacity_);
  names_.push_back(pass);
  open_.push_back(next_);
  next_ += 2;
  // The begin stamp waits for everything before it (ALL_COMMANDS), so a pass's interval starts
  // when its predecessors are done; the end stamp at ALL_COMMANDS waits for this pass's work.
  vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, pool_, open_.back());
}

void GpuTimer::end(VkCommandBuffer cmd) {
  if (!available_) return;
  HB_ASSERT(!open_.empty());
  vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, pool_, open_.back() + 1);
  open_.pop_back();
}

std::vector<std::pair<std::string, double>> GpuTimer::read(double* frameMs) const {
  std::vector<std::pair<std::string, double>> out;
  if (!available_) {
    if (frameMs) *frameMs = 0;
    return out;
  }
  std::vector<uint64_t> ticks(next_);
  VK_CHECK(vkGetQueryPoolResults(ctx_.device(), pool_, 0, next_, ticks.size() * 8, ticks.data(), 8,
                                 VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
  auto ms = [&](uint32_t a, uint32_t b) {
    uint64_t t0 = ticks[a] & mask_, t1 = ticks[b] & mask_;
    uint64_t d = (t1 - t0) & mask_;  // wraps correctly within the valid bits
    return double(d) * periodNs_ * 1e-6;
  };
  for (uint32_t i = 0; i < names_.size(); ++i) out.emplace_back(names_[i], ms(2 + 2 * i, 3 + 2 * i));
  if (frameMs) *frameMs = ms(0, 1);
  return out;
}

}  // namespace hb
