#include "effects/shadows/raybench_pass.h"

#include <cstring>
#include <vector>

#include "base/errors.h"
#include "gpu/sync.h"
#include "shared/bindings.h"

namespace hb {

RayBenchPass::RayBenchPass(const VulkanContext& ctx, ShadowBackend backend, uint32_t width, uint32_t height,
                           const ShadowInputs& in, const ShadowPass& shadows, const TraceBvh* bvh)
    : ctx_(ctx),
      backend_(backend),
      width_(width),
      height_(height),
      result_(ctx, width, height, VK_FORMAT_R32_UINT,
              VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
              VK_IMAGE_ASPECT_COLOR_BIT),
      sets_(ctx,
            [&] {
              const VkShaderStageFlags st = backend != ShadowBackend::Pipeline
                                                ? VkShaderStageFlags(VK_SHADER_STAGE_COMPUTE_BIT)
                                                : VK_SHADER_STAGE_RAYGEN_BIT_KHR | VK_SHADER_STAGE_MISS_BIT_KHR;
              std::vector<Binding> b{{HB_RAYBENCH_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, st},
                                     {HB_RAYBENCH_LIGHTS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, st},
                                     {HB_RAYBENCH_GRID, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, st},
                                     {HB_RAYBENCH_INDICES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, st},
                                     {HB_RAYBENCH_POSITIONS, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, st},
                                     {HB_RAYBENCH_TRACED, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, st},
                                     {HB_RAYBENCH_TLAS, VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR, st},
                                     {HB_RAYBENCH_RESULT, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, st},
                                     {HB_RAYBENCH_VISIBILITY, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, st}};
              if (backend == ShadowBackend::Compute) {  // our BVH instead of the TLAS
                std::erase_if(b, [](const Binding& x) { return x.binding == HB_RAYBENCH_TLAS; });
                b.push_back({HB_RAYBENCH_BVH_NODES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, st});
                b.push_back({HB_RAYBENCH_BVH_TRIANGLES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, st});
              }
              return b;
            }()),
      compute_(ctx) {
  sets_.writeBuffer(0, HB_RAYBENCH_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, in.frameConstants->handle());
  sets_.writeBuffer(0, HB_RAYBENCH_LIGHTS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, in.lights->handle());
  sets_.writeBuffer(0, HB_RAYBENCH_GRID, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, in.grid->handle());
  sets_.writeBuffer(0, HB_RAYBENCH_INDICES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, in.indices->handle());
  sets_.writeImage(0, HB_RAYBENCH_POSITIONS, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, shadows.positions().view(),
                   VK_IMAGE_LAYOUT_GENERAL);
  sets_.writeBuffer(0, HB_RAYBENCH_TRACED, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, shadows.traced().handle());
  if (backend == ShadowBackend::Compute) {
    sets_.writeBuffer(0, HB_RAYBENCH_BVH_NODES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, in.bvhNodes->handle());
    sets_.writeBuffer(0, HB_RAYBENCH_BVH_TRIANGLES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, in.bvhTriangles->handle());
  } else {
    sets_.writeAccelerationStructure(0, HB_RAYBENCH_TLAS, in.tlas);
  }
  sets_.writeImage(0, HB_RAYBENCH_RESULT, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, result_.view(), VK_IMAGE_LAYOUT_GENERAL);
  sets_.writeBuffer(0, HB_RAYBENCH_VISIBILITY, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, shadows.visibility().handle());
  const bool stackShared = bvh ? traceStackShared(*bvh, 64) : shadows.settings().raybenchStackShared;
  const SpecConstants spec{{shadows.settings().listMode, bvh ? bvh->stack : shadows.settings().bvhStack,
                            stackShared ? 1u : 0u, bvh ? bvh->width : shadows.settings().bvhWidth}};
  if (backend != ShadowBackend::Pipeline) {
    compute_.createLayout({sets_.layout()}, 0);
    compute_.createCompute(backend == ShadowBackend::Compute ? "raybench_compute.comp" : "raybench_rayquery.comp",
                           spec);
  } else {
    rt_ = std::make_unique<RaygenMissPipeline>(ctx, sets_.layout(), "raybench.rgen", "shadows.rmiss", spec);
  }
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
  VkDescriptorSet set = sets_.set();
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
