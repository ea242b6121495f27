// A pass's resources by the names its shaders declare: the pass provides each resource once
// (provide("Lights", lights)), and each of its pipelines gets a descriptor set whose layout comes
// from its shaders' reflection (ShaderProgram), written from that name table. Both directions are
// checked when the pass is built: a binding a shader reads that the pass did not provide
// (write), and a name the pass provided that none of its shaders reads (checkEveryNameRead),
// each throw std::logic_error naming the pass, the shader and the binding. A pass whose shader
// variant does not read an optional resource therefore does not provide it.
#pragma once
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "gpu/shader_reflection.h"
#include "gpu/vk_pipeline.h"
#include "gpu/vk_resources.h"

namespace hb {

class DescriptorBinder {
 public:
  explicit DescriptorBinder(std::string pass) : pass_(std::move(pass)) {}

  // A uniform or storage buffer (the shader's declaration says which), `range` bytes of it from
  // `offset`. Precondition: no name twice.
  void provide(const std::string& name, const Buffer& buffer, VkDeviceSize offset = 0,
               VkDeviceSize range = VK_WHOLE_SIZE);
  // A sampled image (with `sampler`) or a storage image (no sampler), in `layout` when read.
  void provide(const std::string& name, const Image& image, VkImageLayout layout, VkSampler sampler = VK_NULL_HANDLE);
  // A runtime-sized array of sampled images (bindless textures), each through `sampler`.
  void provide(const std::string& name, const std::vector<Image>& images, VkImageLayout layout, VkSampler sampler);
  void provide(const std::string& name, VkAccelerationStructureKHR tlas);

  // One set of `program`'s reflected layout, every binding written from what was provided; the
  // variable count of a runtime-sized array is the provided array's size. Throws naming the pass,
  // the shader and the binding when a binding was not provided or was provided as another kind.
  std::unique_ptr<DescriptorSets> write(const VulkanContext& ctx, const ShaderProgram& program) const;
  // Throws naming the pass and each name it provided that none of the programs written read.
  void checkEveryNameRead() const;

 private:
  struct Resource {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceSize offset = 0, range = VK_WHOLE_SIZE;
    std::vector<VkImageView> views;  // one, or the runtime-sized array's
    bool array = false;
    VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
    VkSampler sampler = VK_NULL_HANDLE;
    VkAccelerationStructureKHR tlas = VK_NULL_HANDLE;
  };
  void add(const std::string& name, Resource r);
  std::string pass_;
  std::map<std::string, Resource> resources_;
  mutable std::set<std::string> read_;         // names some written program read
  mutable std::vector<std::string> programs_;  // the programs written, for the message
};

}  // namespace hb
