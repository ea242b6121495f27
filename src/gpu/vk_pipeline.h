// Shader modules from the embedded SPIR-V, descriptor sets and pipelines: the small amount of
// plumbing each pass needs, with every handle owned by the object that created it.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "gpu/shader_reflection.h"
#include "gpu/vk_context.h"

namespace hb {

class DescriptorBinder;

// SPIR-V words of shaders/<name>.glsl (name like "depth.vert"); throws if it was not embedded.
std::vector<uint32_t> embeddedSpirv(const std::string& name);
std::vector<std::string> embeddedShaderNames();
// Adds SPIR-V compiled elsewhere (a test's own pass: tests/shaders/) under `name`; `words`
// (bytes long) and `name` outlive every use. Precondition: no shader has that name yet.
void registerSpirv(std::string_view name, const uint32_t* words, size_t bytes);

class ShaderModule {
 public:
  ShaderModule(const VulkanContext& ctx, const std::string& name);
  ShaderModule(const VulkanContext& ctx, const std::vector<uint32_t>& spirv);
  ~ShaderModule();
  ShaderModule(const ShaderModule&) = delete;
  VkShaderModule handle() const { return module_; }

 private:
  const VulkanContext& ctx_;
  VkShaderModule module_ = VK_NULL_HANDLE;
};

struct Binding {
  uint32_t binding;
  VkDescriptorType type;
  VkShaderStageFlags stages;
  uint32_t count = 1;
  bool variableCount = false;  // last binding only: a variable-length (bindless) array
};

// One descriptor set layout, a pool sized for `sets` sets of it, and those sets.
class DescriptorSets {
 public:
  DescriptorSets(const VulkanContext& ctx, const std::vector<Binding>& bindings, uint32_t sets = 1,
                 uint32_t variableCount = 0);
  ~DescriptorSets();
  DescriptorSets(const DescriptorSets&) = delete;
  VkDescriptorSetLayout layout() const { return layout_; }
  VkDescriptorSet set(uint32_t i = 0) const { return sets_[i]; }

  void writeBuffer(uint32_t set, uint32_t binding, VkDescriptorType type, VkBuffer buffer,
                   VkDeviceSize size = VK_WHOLE_SIZE, VkDeviceSize offset = 0) const;
  void writeImage(uint32_t set, uint32_t binding, VkDescriptorType type, VkImageView view, VkImageLayout layout,
                  VkSampler sampler = VK_NULL_HANDLE, uint32_t arrayElement = 0) const;
  void writeAccelerationStructure(uint32_t set, uint32_t binding, VkAccelerationStructureKHR as) const;

 private:
  const VulkanContext& ctx_;
  VkDescriptorSetLayout layout_ = VK_NULL_HANDLE;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  std::vector<VkDescriptorSet> sets_;
};

// Specialization constants: ids 0..n-1 in order, each a 32-bit value.
struct SpecConstants {
  std::vector<uint32_t> values;
};

class Pipeline {
 public:
  Pipeline(const VulkanContext& ctx) : ctx_(ctx) {}
  ~Pipeline();
  Pipeline(const Pipeline&) = delete;
  VkPipeline handle() const { return pipeline_; }
  VkPipelineLayout layout() const { return layout_; }
  VkPipelineBindPoint bindPoint() const { return bindPoint_; }

  // Creates the layout (set layouts + one push-constant range of pushBytes for all stages).
  void createLayout(const std::vector<VkDescriptorSetLayout>& setLayouts, uint32_t pushBytes);
  void createCompute(const std::string& shader, const SpecConstants& spec = {});
  // The layout from `program`'s reflection (its set 0 + pushBytes of push constants) and that set,
  // owned by the pipeline (set()), written from `binder` (which throws naming a binding it lacks).
  void createLayout(const DescriptorBinder& binder, const ShaderProgram& program, uint32_t pushBytes);
  // createLayout from `shader`'s reflection, then its compute pipeline.
  void createCompute(const DescriptorBinder& binder, const std::string& shader, uint32_t pushBytes,
                     const SpecConstants& spec = {});
  // Shader `shader` of `program` (its renumbered SPIR-V) as the compute pipeline of this layout.
  void createCompute(const ShaderProgram& program, std::string_view shader, const SpecConstants& spec = {});
  VkDescriptorSet set() const { return sets_->set(); }  // after createLayout(binder, ...)

  VkPipeline pipeline_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipelineBindPoint bindPoint_ = VK_PIPELINE_BIND_POINT_COMPUTE;

 private:
  void createCompute(VkShaderModule module, const SpecConstants& spec);
  const VulkanContext& ctx_;
  std::unique_ptr<DescriptorSets> sets_;  // createLayout(binder, ...) only
};

// Fills a VkSpecializationInfo for SpecConstants (entries must outlive the call using it).
VkSpecializationInfo specializationInfo(const SpecConstants& spec, std::vector<VkSpecializationMapEntry>& entries);

// What the driver compiled a compute pipeline into (VK_KHR_pipeline_executable_properties): per
// executable {"name", "description", "statistics": {name: value}} with the driver's own names and
// values (NVIDIA: registers, shared memory, spills, ...). Null where the device does not offer the
// extension (DeviceInfo::pipelineStatistics); compute pipelines are created with
// VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR where it does.
nlohmann::json pipelineStatistics(const VulkanContext& ctx, VkPipeline pipeline);

}  // namespace hb
