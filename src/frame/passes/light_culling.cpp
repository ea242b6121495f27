#include "frame/passes/light_culling.h"

#include "base/errors.h"
#include "shared/gpu_types.h"

namespace hb {

namespace {
std::vector<Binding> cullingBindings() {
  const VkShaderStageFlags cs = VK_SHADER_STAGE_COMPUTE_BIT;
  return {{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, cs},
          {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, cs},
          {2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, cs},
          {3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, cs},
          {4, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, cs},
          {5, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, cs}};
}
}  // namespace

LightCulling::LightCulling(const VulkanContext& ctx, const CullingSettings& settings, uint32_t width,
                           uint32_t height, const Buffer& frameConstants, const Buffer& lights, const Image& depth,
                           VkSampler sampler)
    : ctx_(ctx),
      settings_(settings),
      tilesX_((width + settings.tileSize - 1) / settings.tileSize),
      tilesY_((height + settings.tileSize - 1) / settings.tileSize),
      frustums_(ctx, VkDeviceSize(tilesX_) * tilesY_ * sizeof(gpu::TileFrustum), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                false, MemClass::Culling),
      grid_(ctx, VkDeviceSize(tilesX_) * tilesY_ * sizeof(gpu::LightGridEntry),
            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT, false, MemClass::Culling),
      indices_(ctx, VkDeviceSize(tilesX_) * tilesY_ * settings.capacity * sizeof(uint32_t),
               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT, false, MemClass::Culling),
      sets_(ctx, cullingBindings()),
      frustumPipeline_(ctx),
      cullPipeline_(ctx) {
  if (settings.tileSize != 8 && settings.tileSize != 16 && settings.tileSize != 32)
    throw InputError("tile_size " + std::to_string(settings.tileSize) + " is not one of 8, 16, 32");
  HB_ASSERT(settings.capacity == gpu::kMaxLightsPerTile);
  if (settings.depthSlices == 1 || settings.depthSlices > 32)
    throw InputError("depth_slices " + std::to_string(settings.depthSlices) + " is not 0 (off) or 2..32");
  sets_.writeBuffer(0, 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, frameConstants.handle());
  sets_.writeBuffer(0, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, lights.handle());
  sets_.writeBuffer(0, 2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, frustums_.handle());
  sets_.writeBuffer(0, 3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, grid_.handle());
  sets_.writeBuffer(0, 4, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, indices_.handle());
  sets_.writeImage(0, 5, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, depth.view(),
                   VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL, sampler);
  frustumPipeline_.createLayout({sets_.layout()}, 4);
  frustumPipeline_.createCompute("tile_frustums.comp");
  cullPipeline_.createLayout({sets_.layout()}, 4);
  // Specialization constants (light_cull.comp.glsl): 0 tile size, 1 culling on, 2 AABB test,
  // 3 depth slices.
  cullPipeline_.createCompute("light_cull.comp", {{settings.tileSize, settings.lightCulling ? 1u : 0u,
                                                   settings.aabb ? 1u : 0u, settings.depthSlices}});
}

LightCulling::~LightCulling() = default;

void LightCulling::recordFrustums(VkCommandBuffer cmd) const {
  VkDescriptorSet set = sets_.set();
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, frustumPipeline_.handle());
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, frustumPipeline_.layout(), 0, 1, &set, 0, nullptr);
  uint32_t zero = 0;
  vkCmdPushConstants(cmd, frustumPipeline_.layout(), VK_SHADER_STAGE_ALL, 0, 4, &zero);
  vkCmdDispatch(cmd, (tilesX_ * tilesY_ + 63) / 64, 1, 1);
  memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_WRITE_BIT,
                VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_READ_BIT);
}

void LightCulling::recordCulling(VkCommandBuffer cmd, uint32_t lightCount) const {
  VkDescriptorSet set = sets_.set();
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, cullPipeline_.handle());
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, cullPipeline_.layout(), 0, 1, &set, 0, nullptr);
  vkCmdPushConstants(cmd, cullPipeline_.layout(), VK_SHADER_STAGE_ALL, 0, 4, &lightCount);
  vkCmdDispatch(cmd, tilesX_, tilesY_, 1);
}

}  // namespace hb
