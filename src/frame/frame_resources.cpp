#include <algorithm>
#include <utility>

#include <vulkan/vulkan.hpp>                // vk::to_string: a format's name
#include <vulkan/vulkan_format_traits.hpp>  // vk::blockSize: its texel size

#include "base/errors.h"
#include "frame/frame_pass.h"
#include "gpu/vk_resources.h"

namespace hb {

const NamedResource* FrameResources::find(std::string_view name) const {
  for (const NamedResource& r : resources_)
    if (r.name == name) return &r;
  return nullptr;
}

static void addOnce(std::vector<NamedResource>& resources, NamedResource r) {
  for (const NamedResource& other : resources) HB_ASSERT(other.name != r.name);  // published twice
  resources.push_back(std::move(r));
}

void FrameResources::publish(const std::string& name, const Buffer& buffer, std::string format, std::string size) {
  addOnce(resources_, {name, std::move(format), std::move(size), uint64_t(buffer.size()), &buffer});
}

static NamedResource imageResource(const std::string& name, const Image& image, std::string format,
                                   VkImageLayout layout) {
  const vk::Format f = static_cast<vk::Format>(image.format());
  if (format.empty()) format = vk::to_string(f);
  const uint64_t bytes = uint64_t(image.width()) * image.height() * vk::blockSize(f);
  NamedResource r{name,  std::move(format), std::to_string(image.width()) + " x " + std::to_string(image.height()),
                  bytes, nullptr,           &image};
  r.layout = layout;
  return r;
}

void FrameResources::publish(const std::string& name, const Image& image, std::string format, VkImageLayout layout) {
  addOnce(resources_, imageResource(name, image, std::move(format), layout));
}

void FrameResources::replace(const std::string& name, const Image& image, VkImageLayout layout) {
  for (NamedResource& r : resources_)
    if (r.name == name) {
      HB_ASSERT(r.image != nullptr);
      r = imageResource(name, image, "", layout);
      return;
    }
  HB_ASSERT(false);  // nothing to replace
}

VkImageLayout FrameResources::imageLayout(std::string_view name) const {
  const NamedResource* r = find(name);
  HB_ASSERT(r != nullptr && r->image != nullptr);
  return r->layout;
}

void FrameResources::addShadingTerm(ShadingTerm term) {
  const NamedResource* r = find(term.resource);
  HB_ASSERT(r != nullptr);  // published before it is declared
  HB_ASSERT(term.storage == ShadingTerm::Storage::Rgba32fImage ? r->image != nullptr : r->buffer != nullptr);
  terms_.push_back(std::move(term));
}

void FrameResources::publishTlas(const std::string& name, VkAccelerationStructureKHR tlas, uint64_t bytes) {
  NamedResource r{name, "acceleration structure", "the scene's meshes", bytes};
  r.tlas = tlas;
  addOnce(resources_, std::move(r));
}

void FrameResources::publishSampler(const std::string& name, VkSampler sampler) {
  NamedResource r{name, "sampler", "", 0};
  r.sampler = sampler;
  addOnce(resources_, std::move(r));
}

const Buffer* FrameResources::buffer(std::string_view name) const {
  const NamedResource* r = find(name);
  return r ? r->buffer : nullptr;
}

const Image* FrameResources::image(std::string_view name) const {
  const NamedResource* r = find(name);
  return r ? r->image : nullptr;
}

VkAccelerationStructureKHR FrameResources::tlas(std::string_view name) const {
  const NamedResource* r = find(name);
  return r ? r->tlas : VK_NULL_HANDLE;
}

VkSampler FrameResources::sampler(std::string_view name) const {
  const NamedResource* r = find(name);
  return r ? r->sampler : VK_NULL_HANDLE;
}

const Buffer& FrameResources::requireBuffer(std::string_view name) const {
  const Buffer* b = buffer(name);
  HB_ASSERT(b != nullptr);  // a pass reads a resource no earlier part published
  return *b;
}

const Image& FrameResources::requireImage(std::string_view name) const {
  const Image* i = image(name);
  HB_ASSERT(i != nullptr);
  return *i;
}

const BuiltResource* FrameResources::built(std::string_view key) const {
  for (const BuiltResource& r : built_)
    if (r.key == key) return &r;
  return nullptr;
}

BuiltResource* FrameResources::findBuilt(std::string_view key) {
  for (BuiltResource& r : built_)
    if (r.key == key) return &r;
  return nullptr;
}

void FrameResources::addBuilt(BuiltResource r) {
  for (const BuiltResource& other : built_) HB_ASSERT(other.name != r.name);  // two keys under one name
  built_.push_back(std::move(r));
}

void FrameResources::checkType(const BuiltResource& r, std::type_index type) {
  HB_ASSERT(r.type == type);  // one key asked for as two types
}

void FrameResources::use(const std::string& name, const std::string& who) {
  std::vector<std::string>& users = users_[name];
  if (std::find(users.begin(), users.end(), who) == users.end()) users.push_back(who);
}

nlohmann::json FrameResources::toJson() const {
  nlohmann::json j = nlohmann::json::object();
  for (const NamedResource& r : resources_) {
    if (r.sampler != VK_NULL_HANDLE) continue;  // not memory
    j[r.name] = {{"format", r.format}, {"size", r.size}, {"bytes", r.bytes}};
  }
  for (const BuiltResource& b : built_) {
    nlohmann::json& e = j[b.name];
    if (!e.contains("format")) e["format"] = "";  // built, but read by no pass of the frame (raybench's BVH)
    e["key"] = b.key;
    // "bytes" stays what the frame publishes (our BVH's nodes, an LDM set's node pool); built_bytes is all of it.
    if (!e.contains("bytes")) e["bytes"] = b.bytes;
    e["built_bytes"] = b.bytes;
    e["build_ms"] = b.buildMs;
    e["build_clock"] = "cpu";
    e["built_by"] = b.builtBy;
  }
  for (const auto& [name, users] : users_)
    if (j.contains(name)) j[name]["users"] = users;
  return j;
}

}  // namespace hb
