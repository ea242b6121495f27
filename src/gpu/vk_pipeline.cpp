#include "gpu/vk_pipeline.h"

#include <string_view>

#include "base/errors.h"
#include "gpu/descriptor_binder.h"

namespace hb {

struct EmbeddedShader {
  std::string_view name;
  const uint32_t* words;
  size_t bytes;
};
extern const EmbeddedShader kEmbeddedShaders[];

static std::vector<EmbeddedShader>& registeredShaders() {
  static std::vector<EmbeddedShader> shaders;
  return shaders;
}

void registerSpirv(std::string_view name, const uint32_t* words, size_t bytes) {
  for (const std::string& other : embeddedShaderNames()) HB_ASSERT(other != name);  // one shader per name
  registeredShaders().push_back({name, words, bytes});
}

std::vector<uint32_t> embeddedSpirv(const std::string& name) {
  for (const EmbeddedShader* s = kEmbeddedShaders; s->words; ++s)
    if (s->name == name) return std::vector<uint32_t>(s->words, s->words + s->bytes / 4);
  for (const EmbeddedShader& s : registeredShaders())
    if (s.name == name) return std::vector<uint32_t>(s.words, s.words + s.bytes / 4);
  throw std::logic_error("shader \"" + name + "\" is not embedded (is shaders/**/" + name + ".glsl there?)");
}

std::vector<std::string> embeddedShaderNames() {
  std::vector<std::string> names;
  for (const EmbeddedShader* s = kEmbeddedShaders; s->words; ++s) names.emplace_back(s->name);
  for (const EmbeddedShader& s : registeredShaders()) names.emplace_back(s.name);
  return names;
}

ShaderModule::ShaderModule(const VulkanContext& ctx, const std::string& name)
    : ShaderModule(ctx, embeddedSpirv(name)) {}
ShaderModule::ShaderModule(const VulkanContext& ctx, const std::vector<uint32_t>& code) : ctx_(ctx) {
  VkShaderModuleCreateInfo ci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  ci.codeSize = code.size() * 4;
  ci.pCode = code.data();
  VK_CHECK(vkCreateShaderModule(ctx.device(), &ci, nullptr, &module_));
}
ShaderModule::~ShaderModule() { vkDestroyShaderModule(ctx_.device(), module_, nullptr); }

DescriptorSets::DescriptorSets(const VulkanContext& ctx, const std::vector<Binding>& bindings, uint32_t sets,
                               uint32_t variableCount)
    : ctx_(ctx) {
  std::vector<VkDescriptorSetLayoutBinding> lb;
  std::vector<VkDescriptorBindingFlags> flags;
  std::vector<VkDescriptorPoolSize> sizes;
  bool hasVariable = false;
  for (const Binding& b : bindings) {
    uint32_t count = b.variableCount ? variableCount : b.count;
    lb.push_back({b.binding, b.type, b.variableCount ? std::max(count, 1u) : count, b.stages, nullptr});
    flags.push_back(b.variableCount ? VK_DESCRIPTOR_BINDING_VARIABLE_DESCRIPTOR_COUNT_BIT |
                                          VK_DESCRIPTOR_BINDING_PARTIALLY_BOUND_BIT
                                    : 0);
    hasVariable |= b.variableCount;
    sizes.push_back({b.type, std::max(count, 1u) * sets});
  }
  VkDescriptorSetLayoutBindingFlagsCreateInfo fi{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_BINDING_FLAGS_CREATE_INFO};
  fi.bindingCount = uint32_t(flags.size());
  fi.pBindingFlags = flags.data();
  VkDescriptorSetLayoutCreateInfo li{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  li.pNext = hasVariable ? &fi : nullptr;
  li.bindingCount = uint32_t(lb.size());
  li.pBindings = lb.data();
  VK_CHECK(vkCreateDescriptorSetLayout(ctx.device(), &li, nullptr, &layout_));
  VkDescriptorPoolCreateInfo pi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  pi.maxSets = sets;
  pi.poolSizeCount = uint32_t(sizes.size());
  pi.pPoolSizes = sizes.data();
  VK_CHECK(vkCreateDescriptorPool(ctx.device(), &pi, nullptr, &pool_));
  std::vector<VkDescriptorSetLayout> layouts(sets, layout_);
  std::vector<uint32_t> counts(sets, std::max(variableCount, 1u));
  VkDescriptorSetVariableDescriptorCountAllocateInfo vi{
      VK_STRUCTURE_TYPE_DESCRIPTOR_SET_VARIABLE_DESCRIPTOR_COUNT_ALLOCATE_INFO};
  vi.descriptorSetCount = sets;
  vi.pDescriptorCounts = counts.data();
  VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  ai.pNext = hasVariable ? &vi : nullptr;
  ai.descriptorPool = pool_;
  ai.descriptorSetCount = sets;
  ai.pSetLayouts = layouts.data();
  sets_.resize(sets);
  VK_CHECK(vkAllocateDescriptorSets(ctx.device(), &ai, sets_.data()));
}

DescriptorSets::~DescriptorSets() {
  vkDestroyDescriptorPool(ctx_.device(), pool_, nullptr);
  vkDestroyDescriptorSetLayout(ctx_.device(), layout_, nullptr);
}

void DescriptorSets::writeBuffer(uint32_t set, uint32_t binding, VkDescriptorType type, VkBuffer buffer,
                                 VkDeviceSize size, VkDeviceSize offset) const {
  VkDescriptorBufferInfo bi{buffer, offset, size};
  VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  w.dstSet = sets_[set];
  w.dstBinding = binding;
  w.descriptorCount = 1;
  w.descriptorType = type;
  w.pBufferInfo = &bi;
  vkUpdateDescriptorSets(ctx_.device(), 1, &w, 0, nullptr);
}

void DescriptorSets::writeImage(uint32_t set, uint32_t binding, VkDescriptorType type, VkImageView view,
                                VkImageLayout layout, VkSampler sampler, uint32_t arrayElement) const {
  VkDescriptorImageInfo ii{sampler, view, layout};
  VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  w.dstSet = sets_[set];
  w.dstBinding = binding;
  w.dstArrayElement = arrayElement;
  w.descriptorCount = 1;
  w.descriptorType = type;
  w.pImageInfo = &ii;
  vkUpdateDescriptorSets(ctx_.device(), 1, &w, 0, nullptr);
}

void DescriptorSets::writeAccelerationStructure(uint32_t set, uint32_t binding, VkAccelerationStructureKHR as) const {
  VkWriteDescriptorSetAccelerationStructureKHR asi{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET_ACCELERATION_STRUCTURE_KHR};
  asi.accelerationStructureCount = 1;
  asi.pAccelerationStructures = &as;
  VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  w.pNext = &asi;
  w.dstSet = sets_[set];
  w.dstBinding = binding;
  w.descriptorCount = 1;
  w.descriptorType = VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR;
  vkUpdateDescriptorSets(ctx_.device(), 1, &w, 0, nullptr);
}

Pipeline::~Pipeline() {
  if (pipeline_) vkDestroyPipeline(ctx_.device(), pipeline_, nullptr);
  if (layout_) vkDestroyPipelineLayout(ctx_.device(), layout_, nullptr);
}

void Pipeline::createLayout(const std::vector<VkDescriptorSetLayout>& setLayouts, uint32_t pushBytes) {
  VkPushConstantRange range{VK_SHADER_STAGE_ALL, 0, pushBytes};
  VkPipelineLayoutCreateInfo li{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  li.setLayoutCount = uint32_t(setLayouts.size());
  li.pSetLayouts = setLayouts.data();
  li.pushConstantRangeCount = pushBytes ? 1 : 0;
  li.pPushConstantRanges = &range;
  VK_CHECK(vkCreatePipelineLayout(ctx_.device(), &li, nullptr, &layout_));
}

VkSpecializationInfo specializationInfo(const SpecConstants& spec, std::vector<VkSpecializationMapEntry>& entries) {
  entries.clear();
  for (uint32_t i = 0; i < spec.values.size(); ++i) entries.push_back({i, i * 4, 4});
  VkSpecializationInfo si{};
  si.mapEntryCount = uint32_t(entries.size());
  si.pMapEntries = entries.data();
  si.dataSize = spec.values.size() * 4;
  si.pData = spec.values.data();
  return si;
}

void Pipeline::createLayout(const DescriptorBinder& binder, const ShaderProgram& program, uint32_t pushBytes) {
  sets_ = binder.write(ctx_, program);
  createLayout({sets_->layout()}, pushBytes);
}

void Pipeline::createCompute(const DescriptorBinder& binder, const std::string& shader, uint32_t pushBytes,
                             const SpecConstants& spec) {
  ShaderProgram program({shader});
  createLayout(binder, program, pushBytes);
  createCompute(ShaderModule(ctx_, program.spirv(0)).handle(), spec);
}

void Pipeline::createCompute(const ShaderProgram& program, std::string_view shader, const SpecConstants& spec) {
  createCompute(ShaderModule(ctx_, program.spirv(shader)).handle(), spec);
}

void Pipeline::createCompute(const std::string& shader, const SpecConstants& spec) {
  createCompute(ShaderModule(ctx_, shader).handle(), spec);
}

void Pipeline::createCompute(VkShaderModule module, const SpecConstants& spec) {
  std::vector<VkSpecializationMapEntry> entries;
  VkSpecializationInfo si = specializationInfo(spec, entries);
  VkComputePipelineCreateInfo ci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  ci.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  ci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  ci.stage.module = module;
  ci.stage.pName = "main";
  ci.stage.pSpecializationInfo = spec.values.empty() ? nullptr : &si;
  ci.layout = layout_;
  if (ctx_.info().pipelineStatistics) ci.flags |= VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR;
  bindPoint_ = VK_PIPELINE_BIND_POINT_COMPUTE;
  VK_CHECK(vkCreateComputePipelines(ctx_.device(), VK_NULL_HANDLE, 1, &ci, nullptr, &pipeline_));
}

nlohmann::json pipelineStatistics(const VulkanContext& ctx, VkPipeline pipeline) {
  if (!ctx.info().pipelineStatistics) return nullptr;
  VkPipelineInfoKHR pi{VK_STRUCTURE_TYPE_PIPELINE_INFO_KHR};
  pi.pipeline = pipeline;
  uint32_t n = 0;
  VK_CHECK(ctx.getExecutableProperties(ctx.device(), &pi, &n, nullptr));
  std::vector<VkPipelineExecutablePropertiesKHR> props(n, {VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_PROPERTIES_KHR});
  VK_CHECK(ctx.getExecutableProperties(ctx.device(), &pi, &n, props.data()));
  nlohmann::json out = nlohmann::json::array();
  for (uint32_t e = 0; e < n; ++e) {
    VkPipelineExecutableInfoKHR ei{VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_INFO_KHR};
    ei.pipeline = pipeline;
    ei.executableIndex = e;
    uint32_t m = 0;
    VK_CHECK(ctx.getExecutableStatistics(ctx.device(), &ei, &m, nullptr));
    std::vector<VkPipelineExecutableStatisticKHR> stats(m, {VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_STATISTIC_KHR});
    VK_CHECK(ctx.getExecutableStatistics(ctx.device(), &ei, &m, stats.data()));
    nlohmann::json values = nlohmann::json::object();
    for (const VkPipelineExecutableStatisticKHR& st : stats) {
      nlohmann::json v;
      switch (st.format) {
        case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_BOOL32_KHR: v = st.value.b32 == VK_TRUE; break;
        case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_INT64_KHR: v = st.value.i64; break;
        case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_UINT64_KHR: v = st.value.u64; break;
        case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_FLOAT64_KHR: v = st.value.f64; break;
        default: continue;
      }
      values[st.name] = v;
    }
    out.push_back({{"name", props[e].name}, {"description", props[e].description}, {"statistics", values}});
  }
  return out;
}

}  // namespace hb
