// Owned GPU resources: buffers and images with their memory, destroyed with their owner.
// Every byte allocated is counted per resource class so reports can list memory per variant.
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "gpu/vk_context.h"

namespace hb {

enum class MemClass { Geometry, AccelerationStructure, Culling, Images, Staging, Other };
const char* memClassName(MemClass c);

// Bytes currently allocated per class (process-wide; contexts are used one at a time).
std::map<std::string, uint64_t> memoryByClass();

class Buffer {
 public:
  Buffer() = default;
  // hostVisible: mapped for the buffer's lifetime (persistently). deviceAddress adds
  // SHADER_DEVICE_ADDRESS usage and allocation flag.
  Buffer(const VulkanContext& ctx, VkDeviceSize size, VkBufferUsageFlags usage, bool hostVisible,
         MemClass cls = MemClass::Other);
  ~Buffer();
  Buffer(Buffer&& o) noexcept;
  Buffer& operator=(Buffer&& o) noexcept;
  Buffer(const Buffer&) = delete;

  VkBuffer handle() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  void* mapped() const { return mapped_; }
  VkDeviceAddress address() const { return address_; }
  explicit operator bool() const { return buffer_ != VK_NULL_HANDLE; }

 private:
  void release();
  const VulkanContext* ctx_ = nullptr;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize size_ = 0;
  void* mapped_ = nullptr;
  VkDeviceAddress address_ = 0;
  MemClass cls_ = MemClass::Other;
};

// Uploads bytes into a new device-local buffer (through a staging buffer).
Buffer uploadBuffer(const VulkanContext& ctx, const void* data, VkDeviceSize size, VkBufferUsageFlags usage,
                    MemClass cls);

class Image {
 public:
  Image() = default;
  Image(const VulkanContext& ctx, uint32_t width, uint32_t height, VkFormat format, VkImageUsageFlags usage,
        VkImageAspectFlags aspect, uint32_t mipLevels = 1, MemClass cls = MemClass::Images);
  ~Image();
  Image(Image&& o) noexcept;
  Image& operator=(Image&& o) noexcept;
  Image(const Image&) = delete;

  VkImage handle() const { return image_; }
  VkImageView view() const { return view_; }
  VkFormat format() const { return format_; }
  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }
  uint32_t mipLevels() const { return mips_; }
  VkImageAspectFlags aspect() const { return aspect_; }
  explicit operator bool() const { return image_ != VK_NULL_HANDLE; }

 private:
  void release();
  const VulkanContext* ctx_ = nullptr;
  VkImage image_ = VK_NULL_HANDLE;
  VkImageView view_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkFormat format_ = VK_FORMAT_UNDEFINED;
  uint32_t width_ = 0, height_ = 0, mips_ = 1;
  VkDeviceSize bytes_ = 0;
  VkImageAspectFlags aspect_ = 0;
  MemClass cls_ = MemClass::Images;
};

// A whole-image layout transition (all mips) with synchronization2 masks.
void imageBarrier(VkCommandBuffer cmd, const Image& image, VkImageLayout from, VkImageLayout to,
                  VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dstStage,
                  VkAccessFlags2 dstAccess);
// A global memory barrier.
void memoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
                   VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess);

// Copies mip 0 of an image (in layout `layout`, restored afterwards) into host memory.
std::vector<uint8_t> readbackImage(const VulkanContext& ctx, const Image& image, VkImageLayout layout,
                                   uint32_t bytesPerPixel);
std::vector<uint8_t> readbackBuffer(const VulkanContext& ctx, const Buffer& buffer);

}  // namespace hb
