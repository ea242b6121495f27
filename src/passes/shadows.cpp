#include "passes/shadows.h"

#include <cstring>

#include "errors.h"
#include "shared/gpu_types.h"

namespace hb {

const char* toString(ShadowBackend b) { return b == ShadowBackend::RayQuery ? "rayquery" : "pipeline"; }

namespace {

VkDeviceSize alignUp(VkDeviceSize v, VkDeviceSize a) { return (v + a - 1) / a * a; }

std::vector<Binding> shadowBindings(VkShaderStageFlags stages) {
  return {{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, stages},
          {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, stages},
          {2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, stages},
          {3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, stages},
          {4, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, stages},
          {5, VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR, stages},
          {6, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, stages},
          {7, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, stages},
          {8, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, stages},
          {9, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, stages}};
}

VkShaderStageFlags stagesFor(ShadowBackend b) {
  return b == ShadowBackend::RayQuery ? VK_SHADER_STAGE_COMPUTE_BIT
                                      : VK_SHADER_STAGE_RAYGEN_BIT_KHR | VK_SHADER_STAGE_MISS_BIT_KHR;
}

}  // namespace

struct ShadowPass::Variant {
  const VulkanContext& ctx;
  Pipeline pipeline;
  Buffer sbt;
  VkStridedDeviceAddressRegionKHR raygen{}, miss{}, hit{}, callable{};

  Variant(const VulkanContext& c, const ShadowSettings& s, VkDescriptorSetLayout layout, bool analysis)
      : ctx(c), pipeline(c) {
    pipeline.createLayout({layout}, 0);
    SpecConstants spec{{s.tileSize, s.normals, s.worldPos, s.rangeTest ? 1u : 0u, analysis ? 1u : 0u}};
    if (s.backend == ShadowBackend::RayQuery) {
      pipeline.createCompute("shadows_rayquery.comp", spec);
      return;
    }
    // Ray-tracing pipeline: group 0 = ray generation, group 1 = miss; no hit groups (the rays skip
    // closest-hit shaders and all geometry is opaque).
    ShaderModule rgen(c, "shadows.rgen"), rmiss(c, "shadows.rmiss");
    std::vector<VkSpecializationMapEntry> entries;
    VkSpecializationInfo si = specializationInfo(spec, entries);
    VkPipelineShaderStageCreateInfo stages[2] = {{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO},
                                                 {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO}};
    stages[0].stage = VK_SHADER_STAGE_RAYGEN_BIT_KHR;
    stages[0].module = rgen.handle();
    stages[0].pName = "main";
    stages[0].pSpecializationInfo = &si;
    stages[1].stage = VK_SHADER_STAGE_MISS_BIT_KHR;
    stages[1].module = rmiss.handle();
    stages[1].pName = "main";
    VkRayTracingShaderGroupCreateInfoKHR groups[2] = {{VK_STRUCTURE_TYPE_RAY_TRACING_SHADER_GROUP_CREATE_INFO_KHR},
                                                      {VK_STRUCTURE_TYPE_RAY_TRACING_SHADER_GROUP_CREATE_INFO_KHR}};
    for (uint32_t g = 0; g < 2; ++g) {
      groups[g].type = VK_RAY_TRACING_SHADER_GROUP_TYPE_GENERAL_KHR;
      groups[g].generalShader = g;
      groups[g].closestHitShader = VK_SHADER_UNUSED_KHR;
      groups[g].anyHitShader = VK_SHADER_UNUSED_KHR;
      groups[g].intersectionShader = VK_SHADER_UNUSED_KHR;
    }
    VkRayTracingPipelineCreateInfoKHR ci{VK_STRUCTURE_TYPE_RAY_TRACING_PIPELINE_CREATE_INFO_KHR};
    ci.stageCount = 2;
    ci.pStages = stages;
    ci.groupCount = 2;
    ci.pGroups = groups;
    ci.maxPipelineRayRecursionDepth = 1;
    ci.layout = pipeline.layout();
    VK_CHECK(c.rt().createRayTracingPipelines(c.device(), VK_NULL_HANDLE, VK_NULL_HANDLE, 1, &ci, nullptr,
                                               &pipeline.pipeline_));
    pipeline.bindPoint_ = VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR;

    // Shader binding table: each region starts at a shaderGroupBaseAlignment boundary.
    const auto& props = c.rtPipelineProps();
    const uint32_t handleSize = props.shaderGroupHandleSize;
    const VkDeviceSize stride = alignUp(handleSize, props.shaderGroupHandleAlignment);
    const VkDeviceSize base = props.shaderGroupBaseAlignment;
    std::vector<uint8_t> handles(2 * handleSize);
    VK_CHECK(c.rt().getShaderGroupHandles(c.device(), pipeline.handle(), 0, 2, handles.size(), handles.data()));
    const VkDeviceSize missOffset = alignUp(stride, base);
    sbt = Buffer(c, missOffset + alignUp(stride, base) + base,
                 VK_BUFFER_USAGE_SHADER_BINDING_TABLE_BIT_KHR | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT, true,
                 MemClass::Other);
    const VkDeviceAddress start = alignUp(sbt.address(), base);
    uint8_t* mapped = static_cast<uint8_t*>(sbt.mapped()) + (start - sbt.address());
    std::memcpy(mapped, handles.data(), handleSize);
    std::memcpy(mapped + missOffset, handles.data() + handleSize, handleSize);
    raygen = {start, stride, stride};  // the raygen region's size must equal its stride
    miss = {start + missOffset, stride, stride};
  }
};

ShadowPass::ShadowPass(const VulkanContext& ctx, const ShadowSettings& settings, uint32_t width, uint32_t height,
                       const ShadowInputs& in)
    : ctx_(ctx),
      settings_(settings),
      width_(width),
      height_(height),
      visibility_(ctx, width, height, VK_FORMAT_R32_UINT,
                  VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                  VK_IMAGE_ASPECT_COLOR_BIT),
      accounting_(ctx, width, height, VK_FORMAT_R32_UINT, VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                  VK_IMAGE_ASPECT_COLOR_BIT),
      normals_(ctx, width, height, VK_FORMAT_R32G32B32A32_SFLOAT,
               VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, VK_IMAGE_ASPECT_COLOR_BIT),
      positions_(ctx, width, height, VK_FORMAT_R32G32B32A32_SFLOAT,
                 VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, VK_IMAGE_ASPECT_COLOR_BIT),
      sets_(ctx, shadowBindings(stagesFor(settings.backend))) {
  if (settings.backend == ShadowBackend::RayQuery && !ctx.info().rayQuery)
    throw InputError("backend=rayquery: device \"" + ctx.info().name +
                     "\" has no VK_KHR_ray_query; use backend=pipeline or backend=auto");
  if (settings.backend == ShadowBackend::Pipeline && !ctx.info().rayTracingPipeline)
    throw InputError("backend=pipeline: device \"" + ctx.info().name +
                     "\" has no VK_KHR_ray_tracing_pipeline; use backend=rayquery or backend=auto");
  sets_.writeBuffer(0, 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, in.frameConstants->handle());
  sets_.writeBuffer(0, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, in.lights->handle());
  sets_.writeBuffer(0, 2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, in.grid->handle());
  sets_.writeBuffer(0, 3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, in.indices->handle());
  sets_.writeImage(0, 4, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, in.depth->view(),
                   VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL, in.sampler);
  sets_.writeAccelerationStructure(0, 5, in.tlas);
  const Image* images[4] = {&visibility_, &accounting_, &normals_, &positions_};
  for (uint32_t i = 0; i < 4; ++i)
    sets_.writeImage(0, 6 + i, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, images[i]->view(), VK_IMAGE_LAYOUT_GENERAL);
  timed_ = std::make_unique<Variant>(ctx, settings, sets_.layout(), false);
  analysis_ = std::make_unique<Variant>(ctx, settings, sets_.layout(), true);
  ctx.submitAndWait([&](VkCommandBuffer cmd) {
    for (const Image* img : images)
      imageBarrier(cmd, *img, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_NONE, 0,
                   VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
  });
}

ShadowPass::~ShadowPass() = default;

void ShadowPass::record(VkCommandBuffer cmd, bool analysis) const {
  const Variant& v = analysis ? *analysis_ : *timed_;
  VkDescriptorSet set = sets_.set();
  vkCmdBindPipeline(cmd, v.pipeline.bindPoint(), v.pipeline.handle());
  vkCmdBindDescriptorSets(cmd, v.pipeline.bindPoint(), v.pipeline.layout(), 0, 1, &set, 0, nullptr);
  if (settings_.backend == ShadowBackend::RayQuery) {
    const uint32_t t = settings_.tileSize;
    vkCmdDispatch(cmd, (width_ + t - 1) / t, (height_ + t - 1) / t, 1);
  } else {
    ctx_.rt().cmdTraceRays(cmd, &v.raygen, &v.miss, &v.hit, &v.callable, width_, height_, 1);
  }
}

}  // namespace hb
