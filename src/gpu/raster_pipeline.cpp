#include "gpu/raster_pipeline.h"

#include "base/errors.h"
#include "shared/gpu_types.h"

namespace hb {

VkPipeline createRasterPipeline(const VulkanContext& ctx, const RasterPipelineDesc& d) {
  HB_ASSERT(d.vertexAttributes == 0 || d.vertexAttributes == 1 || d.vertexAttributes == 3);
  VkPipelineShaderStageCreateInfo stages[2] = {{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO},
                                               {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO}};
  stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
  stages[0].module = d.vertex;
  stages[0].pName = "main";
  stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
  stages[1].module = d.fragment;
  stages[1].pName = "main";
  stages[1].pSpecializationInfo = d.fragmentSpec;
  VkVertexInputBindingDescription vb{0, sizeof(Vertex), VK_VERTEX_INPUT_RATE_VERTEX};
  VkVertexInputAttributeDescription va[3] = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, position)},
                                             {1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, normal)},
                                             {2, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(Vertex, uv)}};
  VkPipelineVertexInputStateCreateInfo vi{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
  vi.vertexBindingDescriptionCount = d.vertexAttributes ? 1 : 0;
  vi.pVertexBindingDescriptions = &vb;
  vi.vertexAttributeDescriptionCount = d.vertexAttributes;
  vi.pVertexAttributeDescriptions = va;
  VkPipelineInputAssemblyStateCreateInfo ia{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
  ia.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  VkPipelineViewportStateCreateInfo vp{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
  vp.viewportCount = 1;
  vp.scissorCount = 1;
  VkPipelineRasterizationStateCreateInfo rs{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
  rs.polygonMode = VK_POLYGON_MODE_FILL;
  rs.cullMode = VK_CULL_MODE_NONE;
  rs.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
  rs.lineWidth = 1.0f;
  if (d.depthBiasConstant != 0.0f || d.depthBiasSlope != 0.0f) {
    rs.depthBiasEnable = VK_TRUE;
    rs.depthBiasConstantFactor = d.depthBiasConstant;
    rs.depthBiasSlopeFactor = d.depthBiasSlope;
  }
  VkPipelineMultisampleStateCreateInfo ms{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
  ms.rasterizationSamples = d.samples;
  VkPipelineDepthStencilStateCreateInfo ds{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
  ds.depthTestEnable = d.depthTest ? VK_TRUE : VK_FALSE;
  ds.depthWriteEnable = d.depthTest && d.depthWrite ? VK_TRUE : VK_FALSE;
  ds.depthCompareOp = d.depthCompare;
  std::vector<VkPipelineColorBlendAttachmentState> blend(d.colorFormats.size());
  for (auto& b : blend) {
    b.colorWriteMask = d.colorWrites ? 0xF : 0;
    if (d.additiveBlend) {
      b.blendEnable = VK_TRUE;
      b.srcColorBlendFactor = b.dstColorBlendFactor = b.srcAlphaBlendFactor = b.dstAlphaBlendFactor =
          VK_BLEND_FACTOR_ONE;
      b.colorBlendOp = b.alphaBlendOp = VK_BLEND_OP_ADD;
    }
  }
  VkPipelineColorBlendStateCreateInfo cb{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  cb.attachmentCount = uint32_t(blend.size());
  cb.pAttachments = blend.data();
  VkDynamicState dyn[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
  VkPipelineDynamicStateCreateInfo dy{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
  dy.dynamicStateCount = 2;
  dy.pDynamicStates = dyn;
  VkPipelineRenderingCreateInfo ri{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
  ri.colorAttachmentCount = uint32_t(d.colorFormats.size());
  ri.pColorAttachmentFormats = d.colorFormats.data();
  ri.depthAttachmentFormat = d.depthTest ? d.depthFormat : VK_FORMAT_UNDEFINED;
  VkGraphicsPipelineCreateInfo gi{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
  gi.pNext = &ri;
  gi.stageCount = d.fragment ? 2 : 1;
  gi.pStages = stages;
  gi.pVertexInputState = &vi;
  gi.pInputAssemblyState = &ia;
  gi.pViewportState = &vp;
  gi.pRasterizationState = &rs;
  gi.pMultisampleState = &ms;
  gi.pDepthStencilState = &ds;
  gi.pColorBlendState = &cb;
  gi.pDynamicState = &dy;
  gi.layout = d.layout;
  VkPipeline pipeline = VK_NULL_HANDLE;
  VK_CHECK(vkCreateGraphicsPipelines(ctx.device(), VK_NULL_HANDLE, 1, &gi, nullptr, &pipeline));
  return pipeline;
}

void drawScene(VkCommandBuffer cmd, const GpuScene& scene, VkPipelineLayout layout, const glm::mat4& viewProj,
               uint32_t width, uint32_t height, uint32_t instances) {
  VkViewport viewport{0, 0, float(width), float(height), 0.0f, 1.0f};
  VkRect2D scissor{{0, 0}, {width, height}};
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &scissor);
  VkDeviceSize offset = 0;
  VkBuffer vb = scene.vertices().handle();
  vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
  vkCmdBindIndexBuffer(cmd, scene.indices().handle(), 0, VK_INDEX_TYPE_UINT32);
  uint32_t triangleBase = 0;  // the order of GpuScene::worldTriangles()
  for (const DrawItem& d : scene.draws()) {
    gpu::DrawConstants dc{viewProj * d.model, d.model, d.material, d.firstIndex, d.vertexOffset, triangleBase};
    vkCmdPushConstants(cmd, layout, VK_SHADER_STAGE_ALL, 0, sizeof dc, &dc);
    vkCmdDrawIndexed(cmd, d.indexCount, instances, d.firstIndex, int32_t(d.vertexOffset), 0);
    triangleBase += d.indexCount / 3;
  }
}

}  // namespace hb
