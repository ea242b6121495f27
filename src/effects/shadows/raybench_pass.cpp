#include "effects/shadows/raybench_pass.h"

#include <cstring>
#include <vector>

#include "base/errors.h"
#include "gpu/descriptor_binder.h"
#include "gpu/sync.h"

namespace hb {

RayBenchPass::RayBenchPass(const VulkanContext& ctx, RtBackend backend, uint32_t width, uint32_t height,
                           const ShadowInputs& in, const ShadowPass& shadows, const TraceBvh* bvh)
    : ctx_(ctx),
      backend_(backend),
      width_(width),
      height_(height),
      result_(ctx, width, height, VK_FORMAT_R32_UINT,
              VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
              VK_IMAGE_ASPECT_COLOR_BIT),
      compute_(ctx) {
  DescriptorBinder binder("raybench");
  binder.provide("Frame", *in.frameConstants);
  binder.provide("Lights", *in.lights);
  binder.provide("Grid", *in.grid);
  binder.provide("Indices", *in.indices);
  binder.provide("positionImage", shadows.positions(), VK_IMAGE_LAYOUT_GENERAL);
  binder.provide("Traced", shadows.traced());
  if (backend == RtBackend::Compute) {
    binder.provide("BvhNodes", *in.bvhNodes);
    binder.provide("BvhTriangles", *in.bvhTriangles);
  } else {
    binder.provide("tlas", in.tlas);
  }
  binder.provide("resultImage", result_, VK_IMAGE_LAYOUT_GENERAL);
  binder.provide("Visibility", shadows.visibility());
  const bool stackShared = bvh ? traceStackShared(*bvh, 64) : shadows.settings().raybenchStackShared;
  const SpecConstants spec{{shadows.settings().listMode, bvh ? bvh->stack : shadows.settings().bvhStack,
                            stackShared ? 1u : 0u, bvh ? bvh->width : shadows.settings().bvhWidth}};
  if (backend != RtBackend::Pipeline) {
    compute_.createCompute(binder, backend == RtBackend::Compute ? "raybench_compute.comp" : "raybench_rayquery.comp",
                           0, spec);
  } else {
    rt_ = std::make_unique<RaygenMissPipeline>(ctx, binder, "raybench.rgen", "shadows.rmiss", spec);
  }
  binder.checkEveryNameRead();
  // Cleared once, so that the pixels raybench never writes (sky) read back as 0.
  ctx.submitAndWait([&](VkCommandBuffer cmd) {
    Sync sync;
    sync.use(cmd, {{result_, access::kFill.in(VK_IMAGE_LAYOUT_GENERAL).discarding()}});
    const VkClearColorValue zero{};
    const VkImageSubresourceRange all{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdClearColorImage(cmd, result_.handle(), VK_IMAGE_LAYOUT_GENERAL, &zero, 1, &all);
  });
}

RayBenchPass::~RayBenchPass() = default;

void RayBenchPass::record(VkCommandBuffer cmd) const {
  const Pipeline& p = rt_ ? rt_->pipeline() : compute_;
  VkDescriptorSet set = p.set();
  vkCmdBindPipeline(cmd, p.bindPoint(), p.handle());
  vkCmdBindDescriptorSets(cmd, p.bindPoint(), p.layout(), 0, 1, &set, 0, nullptr);
  if (rt_)
    rt_->traceRays(cmd, width_, height_);
  else
    vkCmdDispatch(cmd, (width_ + 7) / 8, (height_ + 7) / 8, 1);
}

std::vector<uint32_t> RayBenchPass::readResult() const {
  const std::vector<uint8_t> bytes = readbackImage(ctx_, result_, VK_IMAGE_LAYOUT_GENERAL, sizeof(uint32_t));
  std::vector<uint32_t> counts(size_t(width_) * height_);
  HB_ASSERT(bytes.size() == counts.size() * sizeof(uint32_t));
  std::memcpy(counts.data(), bytes.data(), bytes.size());
  return counts;
}

}  // namespace hb
