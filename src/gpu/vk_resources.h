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

// v rounded up to a multiple of a (a > 0).
inline VkDeviceSize alignUp(VkDeviceSize v, VkDeviceSize a) { return (v + a - 1) / a * a; }

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

  VkBuffer handle() const { return f_.buffer; }
  VkDeviceSize size() const { return f_.size; }
  void* mapped() const { return f_.mapped; }
  VkDeviceAddress address() const { return f_.address; }
  explicit operator bool() const { return f_.buffer != VK_NULL_HANDLE; }

 private:
  void release();
  // Everything a Buffer owns, in one value so that a move is one exchange.
  struct Fields {
    const VulkanContext* ctx = nullptr;
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkDeviceSize size = 0;
    void* mapped = nullptr;
    VkDeviceAddress address = 0;
    MemClass cls = MemClass::Other;
  } f_;
};

// Uploads bytes into a new device-local buffer (through a staging buffer).
Buffer uploadBuffer(const VulkanContext& ctx, const void* data, VkDeviceSize size, VkBufferUsageFlags usage,
                    MemClass cls);

class Image {
 public:
  Image() = default;
  Image(const VulkanContext& ctx, uint32_t width, uint32_t height, VkFormat format, VkImageUsageFlags usage,
        VkImageAspectFlags aspect, uint32_t mipLevels = 1, MemClass cls = MemClass::Images,
        VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT);
  ~Image();
  Image(Image&& o) noexcept;
  Image& operator=(Image&& o) noexcept;
  Image(const Image&) = delete;

  VkImage handle() const { return f_.image; }
  VkImageView view() const { return f_.view; }
  VkFormat format() const { return f_.format; }
  uint32_t width() const { return f_.width; }
  uint32_t height() const { return f_.height; }
  uint32_t mipLevels() const { return f_.mips; }
  VkImageAspectFlags aspect() const { return f_.aspect; }
  // The layout the commands recorded so far leave the image in: a Sync (gpu/sync.h) keeps it as it
  // records transitions, and starts the next command buffer from it.
  VkImageLayout layout() const { return f_.layout; }
  VkImageLayout* layoutRecord() const { return &f_.layout; }
  explicit operator bool() const { return f_.image != VK_NULL_HANDLE; }

 private:
  void release();
  // Everything an Image owns, in one value so that a move is one exchange.
  struct Fields {
    const VulkanContext* ctx = nullptr;
    VkImage image = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkFormat format = VK_FORMAT_UNDEFINED;
    uint32_t width = 0, height = 0, mips = 1;
    VkDeviceSize bytes = 0;
    VkImageAspectFlags aspect = 0;
    MemClass cls = MemClass::Images;
    mutable VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
  } f_;
};

// Copies mip 0 of an image into host memory, and leaves it in `layout` (where its users expect it).
std::vector<uint8_t> readbackImage(const VulkanContext& ctx, const Image& image, VkImageLayout layout,
                                   uint32_t bytesPerPixel);
std::vector<uint8_t> readbackBuffer(const VulkanContext& ctx, const Buffer& buffer);
// An RGBA16F image read back as floats (4 per pixel).
std::vector<float> readbackHalfImage(const VulkanContext& ctx, const Image& image, VkImageLayout layout);

}  // namespace hb
