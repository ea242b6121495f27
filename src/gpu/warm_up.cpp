#include "gpu/warm_up.h"

#include <algorithm>
#include <chrono>

#include "base/errors.h"
#include "base/text_format.h"
#include "gpu/descriptor_binder.h"
#include "gpu/gpu_timer.h"
#include "gpu/peaks_detail.h"
#include "gpu/sync.h"
#include "gpu/vk_pipeline.h"
#include "gpu/vk_resources.h"

namespace hb {

WarmUp warmUntilSteady(const std::function<double()>& roundMs, const WarmUpPolicy& policy,
                       const std::function<double()>& nowSeconds) {
  HB_ASSERT(policy.window >= 2 && policy.minRounds >= policy.window);
  WarmUp w;
  w.ran = true;
  w.policy = policy;
  const double start = nowSeconds();
  for (;;) {
    w.ms.push_back(roundMs());
    ++w.rounds;
    w.seconds = nowSeconds() - start;
    if (w.ms.size() >= policy.window) {
      std::vector<double> last(w.ms.end() - policy.window, w.ms.end());
      std::sort(last.begin(), last.end());
      const double median = last[last.size() / 2];
      w.spread = median > 0 ? (last.back() - last.front()) / median : 0.0;
      w.settled = w.spread <= policy.tolerance;
    }
    if (w.rounds >= policy.minRounds && w.settled) return w;
    if (w.seconds >= policy.maxSeconds) return w;
  }
}

struct DeviceWarmer::Impl {
  // peaks.comp's modes (gpu/peaks.cpp): 0 reads the buffer, 5 runs fp32 FMA chains.
  struct PushConstants {
    uint32_t elements, iterations, sentinel, pad;
  };
  const VulkanContext& ctx;
  peaks_detail::Sizes sizes;
  Buffer src, dst;
  DescriptorBinder binder{"warm_up"};
  Pipeline read, fma;
  GpuTimer timer;
  Impl(const VulkanContext& c)
      : ctx(c),
        sizes(peaks_detail::sizesFor(c.info())),
        src(c, sizes.bufferBytes, kUsage, false),
        dst(c, sizes.bufferBytes, kUsage, false),
        read(c),
        fma(c),
        timer(c, 1) {
    binder.provide("Src", src);
    binder.provide("Dst", dst);
    binder.provide("DstWords", dst);
    ctx.submitAndWait([&](VkCommandBuffer cmd) {
      vkCmdFillBuffer(cmd, src.handle(), 0, VK_WHOLE_SIZE, 0x01010101u);
      vkCmdFillBuffer(cmd, dst.handle(), 0, VK_WHOLE_SIZE, 0u);
    });
    read.createCompute(binder, "peaks.comp", sizeof(PushConstants), {{0u}});
    fma.createCompute(binder, "peaks.comp", sizeof(PushConstants), {{5u}});
    binder.checkEveryNameRead();
  }
  static constexpr VkBufferUsageFlags kUsage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;

  // A round: 40 times an FMA dispatch and a read of the buffer, one submission, timed by its
  // timestamps (the host clock where the device has none).
  double round() {
    const uint32_t maxGroups = ctx.properties().limits.maxComputeWorkGroupCount[0];
    auto groupsFor = [&](uint32_t threads) { return std::min({(threads + 255u) / 256u, maxGroups, 65535u}); };
    const uint32_t vec4s = sizes.bufferBytes / 16u;
    const auto t0 = std::chrono::steady_clock::now();
    ctx.submitAndWait(
        [&](VkCommandBuffer cmd) {
          if (timer.available()) {
            timer.reset(cmd);
            timer.frameBegin(cmd);
            timer.begin(cmd, "warm_up");
          }
          Sync sync;
          for (int i = 0; i < 40; ++i)
            for (const Pipeline* p : {&fma, &read}) {
              sync.use(cmd, {{src, access::kComputeWrite}, {dst, access::kComputeWrite}});
              const bool isFma = p == &fma;
              const PushConstants pc{isFma ? sizes.fmaThreads : vec4s, isFma ? sizes.fmaIterations : 0u, 0xFFFFFFFFu,
                                     0u};
              vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p->handle());
              VkDescriptorSet s = p->set();
              vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p->layout(), 0, 1, &s, 0, nullptr);
              vkCmdPushConstants(cmd, p->layout(), VK_SHADER_STAGE_ALL, 0, sizeof pc, &pc);
              vkCmdDispatch(cmd, groupsFor(isFma ? sizes.fmaThreads : vec4s), 1, 1);
            }
          if (timer.available()) {
            timer.end(cmd);
            timer.frameEnd(cmd);
          }
        },
        "warming the device");
    double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (timer.available()) {
      const auto passes = timer.read(nullptr);
      if (!passes.empty()) ms = passes.front().second;
    }
    return ms;
  }
};

DeviceWarmer::DeviceWarmer(const VulkanContext& ctx) {
  if (ctx.info().type != "cpu") impl_ = std::make_unique<Impl>(ctx);
}
DeviceWarmer::~DeviceWarmer() = default;

WarmUp DeviceWarmer::warm(const WarmUpPolicy& policy) {
  if (!impl_) {
    WarmUp w;
    w.policy = policy;
    w.skipped = "a CPU device: no clocks to warm";
    return w;
  }
  const auto start = std::chrono::steady_clock::now();
  return warmUntilSteady(
      [&] { return impl_->round(); }, policy,
      [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); });
}

WarmUp warmDevice(const VulkanContext& ctx, const WarmUpPolicy& policy) { return DeviceWarmer(ctx).warm(policy); }

nlohmann::json toJson(const WarmUp& w) {
  if (!w.ran) return {{"ran", false}, {"skipped", w.skipped}};
  return {{"ran", true},
          {"settled", w.settled},
          {"rounds", w.rounds},
          {"seconds", w.seconds},
          {"spread", w.spread},
          {"tolerance", w.policy.tolerance},
          {"window", w.policy.window},
          {"max_seconds", w.policy.maxSeconds},
          {"ms", w.ms}};
}

std::string warmUpWarning(const WarmUp& w) {
  if (!w.ran || w.settled) return "";
  return format(
      "the device never settled: after %u rounds in %.1f s of warm-up its last %u rounds still differed by %.1f %% "
      "(more than %.1f %%); its times may change while it runs (clocks, power or another process)",
      w.rounds, w.seconds, w.policy.window, 100.0 * w.spread, 100.0 * w.policy.tolerance);
}

}  // namespace hb
