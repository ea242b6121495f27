#include "gpu/rt_pipeline.h"

#include <cstring>
#include <memory>

#include "base/errors.h"
#include "gpu/descriptor_binder.h"

namespace hb {

RaygenMissPipeline::RaygenMissPipeline(const VulkanContext& c, VkDescriptorSetLayout layout,
                                       const ShaderProgram& program, const std::string& raygen, const std::string& miss,
                                       const SpecConstants& spec, const std::string& closestHit)
    : ctx_(c), pipeline_(c) {
  HB_ASSERT(c.info().rayTracingPipeline);
  pipeline_.createLayout({layout}, 0);
  std::vector<std::vector<uint32_t>> spirv{program.spirv(raygen), program.spirv(miss)};
  if (!closestHit.empty()) spirv.push_back(program.spirv(closestHit));
  create(spirv, spec);
}

RaygenMissPipeline::RaygenMissPipeline(const VulkanContext& c, const DescriptorBinder& binder,
                                       const std::string& raygen, const std::string& miss, const SpecConstants& spec,
                                       const std::string& closestHit)
    : ctx_(c), pipeline_(c) {
  HB_ASSERT(c.info().rayTracingPipeline);
  std::vector<std::string> shaders{raygen, miss};
  if (!closestHit.empty()) shaders.push_back(closestHit);
  const ShaderProgram program(shaders);
  pipeline_.createLayout(binder, program, 0);
  std::vector<std::vector<uint32_t>> spirv;
  for (size_t i = 0; i < shaders.size(); ++i) spirv.push_back(program.spirv(i));
  create(spirv, spec);
}

void RaygenMissPipeline::create(const std::vector<std::vector<uint32_t>>& spirv, const SpecConstants& spec) {
  const VulkanContext& c = ctx_;
  // Groups: 0 = ray generation, 1 = miss, 2 = the triangle hit group (closest hit), if any.
  const bool hasHit = spirv.size() == 3;
  const uint32_t groupCount = hasHit ? 3 : 2;
  ShaderModule rgen(c, spirv[0]), rmiss(c, spirv[1]);
  std::unique_ptr<ShaderModule> rchit;
  if (hasHit) rchit = std::make_unique<ShaderModule>(c, spirv[2]);
  std::vector<VkSpecializationMapEntry> entries;
  VkSpecializationInfo si = specializationInfo(spec, entries);
  VkPipelineShaderStageCreateInfo stages[3] = {{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO},
                                               {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO},
                                               {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO}};
  stages[0].stage = VK_SHADER_STAGE_RAYGEN_BIT_KHR;
  stages[0].module = rgen.handle();
  stages[0].pName = "main";
  stages[0].pSpecializationInfo = &si;
  stages[1].stage = VK_SHADER_STAGE_MISS_BIT_KHR;
  stages[1].module = rmiss.handle();
  stages[1].pName = "main";
  if (hasHit) {
    stages[2].stage = VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR;
    stages[2].module = rchit->handle();
    stages[2].pName = "main";
    stages[2].pSpecializationInfo = &si;
  }
  VkRayTracingShaderGroupCreateInfoKHR groups[3] = {{VK_STRUCTURE_TYPE_RAY_TRACING_SHADER_GROUP_CREATE_INFO_KHR},
                                                    {VK_STRUCTURE_TYPE_RAY_TRACING_SHADER_GROUP_CREATE_INFO_KHR},
                                                    {VK_STRUCTURE_TYPE_RAY_TRACING_SHADER_GROUP_CREATE_INFO_KHR}};
  for (uint32_t g = 0; g < groupCount; ++g) {
    groups[g].type =
        g < 2 ? VK_RAY_TRACING_SHADER_GROUP_TYPE_GENERAL_KHR : VK_RAY_TRACING_SHADER_GROUP_TYPE_TRIANGLES_HIT_GROUP_KHR;
    groups[g].generalShader = g < 2 ? g : VK_SHADER_UNUSED_KHR;
    groups[g].closestHitShader = g < 2 ? VK_SHADER_UNUSED_KHR : g;
    groups[g].anyHitShader = VK_SHADER_UNUSED_KHR;
    groups[g].intersectionShader = VK_SHADER_UNUSED_KHR;
  }
  VkRayTracingPipelineCreateInfoKHR ci{VK_STRUCTURE_TYPE_RAY_TRACING_PIPELINE_CREATE_INFO_KHR};
  ci.stageCount = groupCount;
  ci.pStages = stages;
  ci.groupCount = groupCount;
  ci.pGroups = groups;
  ci.maxPipelineRayRecursionDepth = 1;
  ci.layout = pipeline_.layout();
  VK_CHECK(c.rt().createRayTracingPipelines(c.device(), VK_NULL_HANDLE, VK_NULL_HANDLE, 1, &ci, nullptr,
                                            &pipeline_.pipeline_));
  pipeline_.bindPoint_ = VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR;

  // Shader binding table: each region starts at a shaderGroupBaseAlignment boundary.
  const auto& props = c.rtPipelineProps();
  const uint32_t handleSize = props.shaderGroupHandleSize;
  const VkDeviceSize stride = alignUp(handleSize, props.shaderGroupHandleAlignment);
  const VkDeviceSize base = props.shaderGroupBaseAlignment;
  std::vector<uint8_t> handles(size_t(groupCount) * handleSize);
  VK_CHECK(c.rt().getShaderGroupHandles(c.device(), pipeline_.handle(), 0, groupCount, handles.size(), handles.data()));
  const VkDeviceSize region = alignUp(stride, base);
  sbt_ = Buffer(c, region * groupCount + base,
                VK_BUFFER_USAGE_SHADER_BINDING_TABLE_BIT_KHR | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT, true,
                MemClass::Other);
  const VkDeviceAddress start = alignUp(sbt_.address(), base);
  uint8_t* mapped = static_cast<uint8_t*>(sbt_.mapped()) + (start - sbt_.address());
  for (uint32_t g = 0; g < groupCount; ++g)
    std::memcpy(mapped + g * region, handles.data() + size_t(g) * handleSize, handleSize);
  raygen_ = {start, stride, stride};  // the raygen region's size must equal its stride
  miss_ = {start + region, stride, stride};
  if (hasHit) hit_ = {start + 2 * region, stride, stride};
}

void RaygenMissPipeline::traceRays(VkCommandBuffer cmd, uint32_t width, uint32_t height) const {
  ctx_.rt().cmdTraceRays(cmd, &raygen_, &miss_, &hit_, &callable_, width, height, 1);
}

}  // namespace hb
