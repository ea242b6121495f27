#include "gpu/gpu_textures.h"

#include <algorithm>
#include <bit>
#include <cstring>

#include "base/errors.h"
#include "shared/gpu_types.h"

namespace hb {

static Image uploadTexture(const VulkanContext& ctx, const Texture& t) {
  const VkFormat format = t.srgb ? VK_FORMAT_R8G8B8A8_SRGB : VK_FORMAT_R8G8B8A8_UNORM;
  const uint32_t mips = std::bit_width(std::max(t.width, t.height));
  Image img(ctx, t.width, t.height, format,
            VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
            VK_IMAGE_ASPECT_COLOR_BIT, mips, MemClass::Images);
  Buffer staging(ctx, t.rgba.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true, MemClass::Staging);
  std::memcpy(staging.mapped(), t.rgba.data(), t.rgba.size());
  ctx.submitAndWait(
      [&](VkCommandBuffer cmd) {
        imageBarrier(cmd, img, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                     VK_PIPELINE_STAGE_2_NONE, 0, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
        VkBufferImageCopy region{};
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.imageExtent = {t.width, t.height, 1};
        vkCmdCopyBufferToImage(cmd, staging.handle(), img.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
        // Mip chain by successive linear blits, each level from the one above.
        int32_t w = int32_t(t.width), h = int32_t(t.height);
        for (uint32_t level = 1; level < mips; ++level) {
          VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
          b.srcStageMask = b.dstStageMask = VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT;
          b.srcAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT;
          b.dstAccessMask = VK_ACCESS_2_TRANSFER_READ_BIT;
          b.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
          b.newLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
          b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
          b.image = img.handle();
          b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, level - 1, 1, 0, 1};
          VkDependencyInfo di{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
          di.imageMemoryBarrierCount = 1;
          di.pImageMemoryBarriers = &b;
          vkCmdPipelineBarrier2(cmd, &di);
          VkImageBlit blit{};
          blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, level - 1, 0, 1};
          blit.srcOffsets[1] = {w, h, 1};
          w = std::max(w / 2, 1);
          h = std::max(h / 2, 1);
          blit.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, level, 0, 1};
          blit.dstOffsets[1] = {w, h, 1};
          vkCmdBlitImage(cmd, img.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, img.handle(),
                         VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit, VK_FILTER_LINEAR);
        }
        // Levels 0..mips-2 are TRANSFER_SRC, the last is TRANSFER_DST: bring each to SHADER_READ_ONLY.
        for (uint32_t level = 0; level < mips; ++level) {
          VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
          b.srcStageMask = VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT;
          b.srcAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_TRANSFER_READ_BIT;
          b.dstStageMask = VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
          b.dstAccessMask = VK_ACCESS_2_SHADER_SAMPLED_READ_BIT;
          b.oldLayout = level + 1 < mips ? VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL : VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
          b.newLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
          b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
          b.image = img.handle();
          b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, level, 1, 0, 1};
          VkDependencyInfo di{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
          di.imageMemoryBarrierCount = 1;
          di.pImageMemoryBarriers = &b;
          vkCmdPipelineBarrier2(cmd, &di);
        }
      },
      "a texture upload");
  return img;
}

GpuTextures::GpuTextures(const VulkanContext& ctx, const Scene& scene) : ctx_(ctx) {
  for (const Texture& t : scene.textures) {
    if (t.width == 0 || t.height == 0 || t.rgba.size() != size_t(t.width) * t.height * 4)
      throw InputError("texture \"" + t.name + "\" has no pixels or a size that does not match its data");
    images_.push_back(uploadTexture(ctx, t));
  }
  if (images_.empty()) {
    Texture white{"white", 1, 1, false, {255, 255, 255, 255}};
    images_.push_back(uploadTexture(ctx, white));
  }
  VkSamplerCreateInfo si{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  si.magFilter = si.minFilter = VK_FILTER_LINEAR;
  si.mipmapMode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
  si.addressModeU = si.addressModeV = si.addressModeW = VK_SAMPLER_ADDRESS_MODE_REPEAT;
  si.maxLod = VK_LOD_CLAMP_NONE;
  VK_CHECK(vkCreateSampler(ctx.device(), &si, nullptr, &sampler_));

  std::vector<gpu::GpuMaterial> mats;
  for (const Material& m : scene.materials)
    mats.push_back(
        {m.baseColorFactor, m.metallicFactor, m.roughnessFactor, m.baseColorTexture, m.metallicRoughnessTexture});
  if (mats.empty()) mats.push_back({glm::vec4(1.0f), 1.0f, 1.0f, -1, -1});
  materials_ = uploadBuffer(ctx, mats.data(), mats.size() * sizeof(gpu::GpuMaterial),
                            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemClass::Geometry);
}

GpuTextures::~GpuTextures() { vkDestroySampler(ctx_.device(), sampler_, nullptr); }

}  // namespace hb
