// What the two raster passes (depth prepass, shading) share: one graphics pipeline description
// over the scene's vertex layout, and the loop that draws every (instance, primitive) with its
// DrawConstants. The passes differ only in shaders, depth test and colour targets.
#pragma once
#include <vector>

#include "gpu/gpu_scene.h"
#include "gpu/vk_pipeline.h"

namespace hb {

struct RasterPipelineDesc {
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkShaderModule vertex = VK_NULL_HANDLE;
  VkShaderModule fragment = VK_NULL_HANDLE;  // none: depth only (the prepass)
  const VkSpecializationInfo* fragmentSpec = nullptr;
  uint32_t vertexAttributes = 1;  // 1: position; 3: position, normal, uv; 0: no vertex input (gl_VertexIndex only)
  bool depthTest = true;          // false: no depth attachment (depthFormat UNDEFINED), no test
  bool depthWrite = true;
  VkCompareOp depthCompare = VK_COMPARE_OP_GREATER_OR_EQUAL;
  float depthBiasConstant = 0.0f;  // both 0: no depth bias
  float depthBiasSlope = 0.0f;
  std::vector<VkFormat> colorFormats;
  bool additiveBlend = false;  // every colour target: dst = src + dst (photon splatting)
  VkFormat depthFormat = VK_FORMAT_D32_SFLOAT;
  VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT;  // multisampling (hardware MSAA)
  bool colorWrites = true;  // false: the colour targets are declared (one rendering) but not written
};

// Triangle lists, no culling (scenes may be open or double-sided; both passes must agree),
// dynamic viewport and scissor, dynamic rendering. Throws DeviceError.
VkPipeline createRasterPipeline(const VulkanContext& ctx, const RasterPipelineDesc& desc);

// Sets viewport and scissor to width×height, binds the scene's buffers and draws every draw
// item with its DrawConstants pushed to `layout` (all stages), `instances` times (gl_InstanceIndex
// 0..instances−1). The pipeline must be bound.
void drawScene(VkCommandBuffer cmd, const GpuScene& scene, VkPipelineLayout layout, const glm::mat4& viewProj,
               uint32_t width, uint32_t height, uint32_t instances = 1);

}  // namespace hb
