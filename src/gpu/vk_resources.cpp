#include "gpu/vk_resources.h"

#include <cstring>

#include <glm/gtc/packing.hpp>

#include <utility>

#include <atomic>
#include <cstring>
#include <mutex>

#include "base/errors.h"
#include "gpu/sync.h"

namespace hb {

namespace {
std::mutex gMemMutex;
std::map<std::string, uint64_t> gMem;
void account(MemClass c, int64_t bytes) {
  std::lock_guard<std::mutex> lock(gMemMutex);
  gMem[memClassName(c)] += uint64_t(bytes);
}
}  // namespace

const char* memClassName(MemClass c) {
  switch (c) {
    case MemClass::Geometry: return "geometry";
    case MemClass::AccelerationStructure: return "acceleration_structures";
    case MemClass::Culling: return "culling";
    case MemClass::Images: return "images";
    case MemClass::Staging: return "staging";
    default: return "other";
  }
}

std::map<std::string, uint64_t> memoryByClass() {
  std::lock_guard<std::mutex> lock(gMemMutex);
  return gMem;
}

Buffer::Buffer(const VulkanContext& ctx, VkDeviceSize size, VkBufferUsageFlags usage, bool hostVisible, MemClass cls) {
  f_.ctx = &ctx;
  f_.size = size;
  f_.cls = cls;
  HB_ASSERT(size > 0);
  VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bi.size = size;
  bi.usage = usage;
  bi.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VK_CHECK(vkCreateBuffer(ctx.device(), &bi, nullptr, &f_.buffer));
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(ctx.device(), f_.buffer, &req);
  VkMemoryAllocateFlagsInfo flags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
  flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
  VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  if (usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT) ai.pNext = &flags;
  ai.allocationSize = req.size;
  ai.memoryTypeIndex = ctx.findMemoryType(
      req.memoryTypeBits, hostVisible ? VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT
                                      : VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  VK_CHECK(vkAllocateMemory(ctx.device(), &ai, nullptr, &f_.memory));
  VK_CHECK(vkBindBufferMemory(ctx.device(), f_.buffer, f_.memory, 0));
  if (hostVisible) VK_CHECK(vkMapMemory(ctx.device(), f_.memory, 0, VK_WHOLE_SIZE, 0, &f_.mapped));
  if (usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT) {
    VkBufferDeviceAddressInfo dai{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
    dai.buffer = f_.buffer;
    f_.address = vkGetBufferDeviceAddress(ctx.device(), &dai);
  }
  account(f_.cls, int64_t(f_.size));
}

void Buffer::release() {
  if (!f_.ctx) return;
  if (f_.buffer) {
    vkDestroyBuffer(f_.ctx->device(), f_.buffer, nullptr);
    account(f_.cls, -int64_t(f_.size));
  }
  if (f_.memory) vkFreeMemory(f_.ctx->device(), f_.memory, nullptr);
  f_ = Fields{};
}

Buffer::~Buffer() { release(); }
Buffer::Buffer(Buffer&& o) noexcept { *this = std::move(o); }
Buffer& Buffer::operator=(Buffer&& o) noexcept {
  if (this != &o) {
    release();
    f_ = std::exchange(o.f_, Fields{});
  }
  return *this;
}

Buffer uploadBuffer(const VulkanContext& ctx, const void* data, VkDeviceSize size, VkBufferUsageFlags usage,
                    MemClass cls) {
  Buffer staging(ctx, size, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true, MemClass::Staging);
  std::memcpy(staging.mapped(), data, size);
  Buffer dst(ctx, size, usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, false, cls);
  ctx.submitAndWait(
      [&](VkCommandBuffer cmd) {
        VkBufferCopy region{0, 0, size};
        vkCmdCopyBuffer(cmd, staging.handle(), dst.handle(), 1, &region);
      },
      "a buffer upload");
  return dst;
}

Image::Image(const VulkanContext& ctx, uint32_t width, uint32_t height, VkFormat format, VkImageUsageFlags usage,
             VkImageAspectFlags aspect, uint32_t mipLevels, MemClass cls, VkSampleCountFlagBits samples) {
  f_ = {&ctx, VK_NULL_HANDLE, VK_NULL_HANDLE, VK_NULL_HANDLE, format, width, height, mipLevels, 0, aspect, cls};
  VkImageCreateInfo ci{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  ci.imageType = VK_IMAGE_TYPE_2D;
  ci.format = format;
  ci.extent = {width, height, 1};
  ci.mipLevels = mipLevels;
  ci.arrayLayers = 1;
  ci.samples = samples;
  ci.tiling = VK_IMAGE_TILING_OPTIMAL;
  ci.usage = usage;
  ci.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  VK_CHECK(vkCreateImage(ctx.device(), &ci, nullptr, &f_.image));
  VkMemoryRequirements req;
  vkGetImageMemoryRequirements(ctx.device(), f_.image, &req);
  VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  ai.allocationSize = req.size;
  ai.memoryTypeIndex = ctx.findMemoryType(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  VK_CHECK(vkAllocateMemory(ctx.device(), &ai, nullptr, &f_.memory));
  VK_CHECK(vkBindImageMemory(ctx.device(), f_.image, f_.memory, 0));
  f_.bytes = req.size;
  VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  vi.image = f_.image;
  vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
  vi.format = format;
  vi.subresourceRange = {aspect, 0, mipLevels, 0, 1};
  VK_CHECK(vkCreateImageView(ctx.device(), &vi, nullptr, &f_.view));
  account(f_.cls, int64_t(f_.bytes));
}

void Image::release() {
  if (!f_.ctx) return;
  if (f_.view) vkDestroyImageView(f_.ctx->device(), f_.view, nullptr);
  if (f_.image) {
    vkDestroyImage(f_.ctx->device(), f_.image, nullptr);
    account(f_.cls, -int64_t(f_.bytes));
  }
  if (f_.memory) vkFreeMemory(f_.ctx->device(), f_.memory, nullptr);
  f_ = Fields{};
}

Image::~Image() { release(); }
Image::Image(Image&& o) noexcept { *this = std::move(o); }
Image& Image::operator=(Image&& o) noexcept {
  if (this != &o) {
    release();
    f_ = std::exchange(o.f_, Fields{});
  }
  return *this;
}

std::vector<uint8_t> readbackImage(const VulkanContext& ctx, const Image& image, VkImageLayout layout,
                                   uint32_t bytesPerPixel) {
  VkDeviceSize size = VkDeviceSize(image.width()) * image.height() * bytesPerPixel;
  Buffer staging(ctx, size, VK_BUFFER_USAGE_TRANSFER_DST_BIT, true, MemClass::Staging);
  ctx.submitAndWait(
      [&](VkCommandBuffer cmd) {
        Sync sync;
        sync.assume(image, access::kAnyWrite);  // whatever wrote it before this command buffer
        sync.use(cmd, {{image, access::kCopyRead}, {staging, access::kCopyWrite}});
        VkBufferImageCopy region{};
        region.imageSubresource = {
            image.aspect() & VK_IMAGE_ASPECT_DEPTH_BIT ? VkImageAspectFlags(VK_IMAGE_ASPECT_DEPTH_BIT) : image.aspect(),
            0, 0, 1};
        region.imageExtent = {image.width(), image.height(), 1};
        vkCmdCopyImageToBuffer(cmd, image.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, staging.handle(), 1, &region);
        sync.use(cmd, {{image, access::kAnyAccess.in(layout)}});  // back where its users expect it
      },
      "an image readback");
  std::vector<uint8_t> out(size);
  std::memcpy(out.data(), staging.mapped(), size);
  return out;
}

std::vector<uint8_t> readbackBuffer(const VulkanContext& ctx, const Buffer& buffer) {
  Buffer staging(ctx, buffer.size(), VK_BUFFER_USAGE_TRANSFER_DST_BIT, true, MemClass::Staging);
  ctx.submitAndWait(
      [&](VkCommandBuffer cmd) {
        Sync sync;
        sync.assume(buffer, access::kAnyWrite);
        sync.use(cmd, {{buffer, access::kCopyRead}, {staging, access::kCopyWrite}});
        VkBufferCopy region{0, 0, buffer.size()};
        vkCmdCopyBuffer(cmd, buffer.handle(), staging.handle(), 1, &region);
      },
      "a buffer readback");
  std::vector<uint8_t> out(buffer.size());
  std::memcpy(out.data(), staging.mapped(), buffer.size());
  return out;
}

std::vector<float> readbackHalfImage(const VulkanContext& ctx, const Image& image, VkImageLayout layout) {
  const std::vector<uint8_t> bytes = readbackImage(ctx, image, layout, 8);
  std::vector<float> out(bytes.size() / 2);
  for (size_t i = 0; i < out.size(); ++i) {
    uint16_t h;
    std::memcpy(&h, bytes.data() + 2 * i, 2);
    out[i] = glm::unpackHalf1x16(h);
  }
  return out;
}

}  // namespace hb
