#include "gpu/descriptor_binder.h"

#include <algorithm>
#include <stdexcept>

#include "base/errors.h"

namespace hb {

void DescriptorBinder::add(const std::string& name, Resource r) {
  HB_ASSERT(!resources_.count(name));  // one resource per name
  resources_.emplace(name, std::move(r));
}

void DescriptorBinder::provide(const std::string& name, const Buffer& buffer, VkDeviceSize offset, VkDeviceSize range) {
  add(name, Resource{.buffer = buffer.handle(), .offset = offset, .range = range});
}

void DescriptorBinder::provide(const std::string& name, const Image& image, VkImageLayout layout, VkSampler sampler) {
  add(name, Resource{.views = {image.view()}, .layout = layout, .sampler = sampler});
}

void DescriptorBinder::provide(const std::string& name, const std::vector<Image>& images, VkImageLayout layout,
                               VkSampler sampler) {
  Resource r{.array = true, .layout = layout, .sampler = sampler};
  for (const Image& image : images) r.views.push_back(image.view());
  add(name, std::move(r));
}

void DescriptorBinder::provide(const std::string& name, VkAccelerationStructureKHR tlas) {
  add(name, Resource{.tlas = tlas});
}

std::unique_ptr<DescriptorSets> DescriptorBinder::write(const VulkanContext& ctx, const ShaderProgram& program) const {
  auto fail = [&](const ShaderBinding& b, const std::string& why) {
    throw std::logic_error("pass " + pass_ + ": shader " + program.label() + " reads binding " + b.name + ", " + why);
  };
  uint32_t variableCount = 0;
  std::vector<Binding> layout;
  for (const ShaderBinding& b : program.bindings()) {
    auto it = resources_.find(b.name);
    if (it == resources_.end()) fail(b, "which the pass does not provide");
    const Resource& r = it->second;
    const bool buffer = b.type == VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER || b.type == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    const bool image =
        b.type == VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER || b.type == VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    const bool tlas = b.type == VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR;
    if (buffer != (r.buffer != VK_NULL_HANDLE) || image != (r.array || !r.views.empty()) ||
        tlas != (r.tlas != VK_NULL_HANDLE) || (b.count == 0) != r.array ||
        (b.type == VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER) != (r.sampler != VK_NULL_HANDLE))
      fail(b, "which the pass provides as another kind of resource");
    if (b.count != 0 && b.count != 1) fail(b, "an array of fixed size, which no pass provides");
    if (b.count == 0) variableCount = uint32_t(r.views.size());
    layout.push_back({b.binding, b.type, b.stages, b.count == 0 ? 0u : 1u, b.count == 0});
    read_.insert(b.name);
  }
  if (std::find(programs_.begin(), programs_.end(), program.label()) == programs_.end())
    programs_.push_back(program.label());
  auto sets = std::make_unique<DescriptorSets>(ctx, layout, 1, variableCount);
  for (const ShaderBinding& b : program.bindings()) {
    const Resource& r = resources_.at(b.name);
    if (r.buffer)
      sets->writeBuffer(0, b.binding, b.type, r.buffer, r.range, r.offset);
    else if (r.tlas)
      sets->writeAccelerationStructure(0, b.binding, r.tlas);
    else
      for (uint32_t i = 0; i < r.views.size(); ++i)
        sets->writeImage(0, b.binding, b.type, r.views[i], r.layout, r.sampler, i);
  }
  return sets;
}

void DescriptorBinder::checkEveryNameRead() const {
  std::string unread;
  for (const auto& [name, resource] : resources_)
    if (!read_.count(name)) unread += (unread.empty() ? "" : ", ") + name;
  std::string shaders;
  for (const std::string& p : programs_) shaders += (shaders.empty() ? "" : ", ") + p;
  if (!unread.empty())
    throw std::logic_error("pass " + pass_ + " provides " + unread + ", which none of its shaders (" + shaders +
                           ") reads");
}

}  // namespace hb
