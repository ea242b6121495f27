#include "gpu/gpu_textures.h"

#include <algorithm>
#include <bit>
#include <cstring>

#include "base/errors.h"
#include "gpu/sync.h"
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
        // Each level goes its own way (written, then read by the next level's blit): one target each.
        std::vector<VkImageLayout> layouts(mips, VK_IMAGE_LAYOUT_UNDEFINED);
        auto level = [&](uint32_t l) {
          return SyncTarget::image(img.handle(), {VK_IMAGE_ASPECT_COLOR_BIT, l, 1, 0, 1}, &layouts[l]);
        };
        Sync sync;
        sync.use(cmd, {{level(0), access::kCopyWrite.discarding()}});
        VkBufferImageCopy region{};
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.imageExtent = {t.width, t.height, 1};
        vkCmdCopyBufferToImage(cmd, staging.handle(), img.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
        // Mip chain by successive linear blits, each level from the one above.
        int32_t w = int32_t(t.width), h = int32_t(t.height);
        for (uint32_t l = 1; l < mips; ++l) {
          sync.use(cmd, {{level(l - 1), access::kBlitRead}, {level(l), access::kBlitWrite.discarding()}});
          VkImageBlit blit{};
          blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, l - 1, 0, 1};
          blit.srcOffsets[1] = {w, h, 1};
          w = std::max(w / 2, 1);
          h = std::max(h / 2, 1);
          blit.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, l, 0, 1};
          blit.dstOffsets[1] = {w, h, 1};
          vkCmdBlitImage(cmd, img.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, img.handle(),
                         VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit, VK_FILTER_LINEAR);
        }
        // Every level to SHADER_READ_ONLY, where the shaders sample it from now on.
        std::vector<Use> sampled;
        for (uint32_t l = 0; l < mips; ++l) sampled.push_back({level(l), access::kSampled});
        sync.use(cmd, sampled);
        *img.layoutRecord() = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
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
