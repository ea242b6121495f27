#include "passes/shading.h"

#include "errors.h"
#include "passes/depth_prepass.h"
#include "shared/gpu_types.h"

namespace hb {

namespace {
std::vector<Binding> shadingBindings() {
  const VkShaderStageFlags fs = VK_SHADER_STAGE_FRAGMENT_BIT;
  return {{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, fs | VK_SHADER_STAGE_VERTEX_BIT},
          {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, fs},
          {2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, fs},
          {3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, fs},
          {4, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, fs},
          {5, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, fs},
          {6, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, fs},
          {7, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, fs},
          {8, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, fs, 0, true}};
}
}  // namespace

ShadingPass::ShadingPass(const VulkanContext& ctx, const GpuScene& scene, uint32_t width, uint32_t height,
                         const ShadingInputs& in)
    : ctx_(ctx),
      scene_(scene),
      in_(in),
      width_(width),
      height_(height),
      textures_(ctx, scene.scene()),
      color_(ctx, width, height, kHdrFormat, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
             VK_IMAGE_ASPECT_COLOR_BIT),
      refNormals_(ctx, width, height, kRefNormalFormat,
                  VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, VK_IMAGE_ASPECT_COLOR_BIT),
      dummyVisibility_(ctx, 1, 1, VK_FORMAT_R32_UINT, VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT,
                       VK_IMAGE_ASPECT_COLOR_BIT),
      sets_(ctx, shadingBindings(), 1, uint32_t(textures_.images().size())),
      layout_(ctx) {
  sets_.writeBuffer(0, 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, in.frameConstants->handle());
  sets_.writeBuffer(0, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, in.lights->handle());
  // Without a culling pass the grid bindings are never read (USE_GRID = 0); any buffer will do.
  sets_.writeBuffer(0, 2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, (in.grid ? in.grid : in.lights)->handle());
  sets_.writeBuffer(0, 3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, (in.indices ? in.indices : in.lights)->handle());
  sets_.writeImage(0, 4, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                   (in.visibility ? in.visibility : &dummyVisibility_)->view(), VK_IMAGE_LAYOUT_GENERAL,
                   in.pointSampler);
  sets_.writeBuffer(0, 5, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, textures_.materials().handle());
  sets_.writeBuffer(0, 6, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, scene.vertices().handle());
  sets_.writeBuffer(0, 7, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, scene.indices().handle());
  for (uint32_t i = 0; i < textures_.images().size(); ++i)
    sets_.writeImage(0, 8, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, textures_.images()[i].view(),
                     VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, textures_.sampler(), i);
  layout_.createLayout({sets_.layout()}, sizeof(gpu::DrawConstants));
  timed_ = createPipeline(false);
  analysis_ = createPipeline(true);
  ctx.submitAndWait([&](VkCommandBuffer cmd) {
    for (const Image* img : {&color_, &refNormals_})
      imageBarrier(cmd, *img, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                   VK_PIPELINE_STAGE_2_NONE, 0, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                   VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    imageBarrier(cmd, dummyVisibility_, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_NONE,
                 0, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
  });
}

ShadingPass::~ShadingPass() {
  if (timed_) vkDestroyPipeline(ctx_.device(), timed_, nullptr);
  if (analysis_) vkDestroyPipeline(ctx_.device(), analysis_, nullptr);
}

VkPipeline ShadingPass::createPipeline(bool analysis) {
  ShaderModule vert(ctx_, "shading.vert"), frag(ctx_, "shading.frag");
  SpecConstants spec{{in_.tileSize, in_.grid ? 1u : 0u, in_.visibility ? 1u : 0u, analysis ? 1u : 0u}};
  std::vector<VkSpecializationMapEntry> entries;
  VkSpecializationInfo si = specializationInfo(spec, entries);
  VkPipelineShaderStageCreateInfo stages[2] = {{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO},
                                               {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO}};
  stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
  stages[0].module = vert.handle();
  stages[0].pName = "main";
  stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
  stages[1].module = frag.handle();
  stages[1].pName = "main";
  stages[1].pSpecializationInfo = &si;
  VkVertexInputBindingDescription vb{0, sizeof(Vertex), VK_VERTEX_INPUT_RATE_VERTEX};
  VkVertexInputAttributeDescription va[3] = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, position)},
                                             {1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(Vertex, normal)},
                                             {2, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(Vertex, uv)}};
  VkPipelineVertexInputStateCreateInfo vi{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
  vi.vertexBindingDescriptionCount = 1;
  vi.pVertexBindingDescriptions = &vb;
  vi.vertexAttributeDescriptionCount = 3;
  vi.pVertexAttributeDescriptions = va;
  VkPipelineInputAssemblyStateCreateInfo ia{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
  ia.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  VkPipelineViewportStateCreateInfo vp{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
  vp.viewportCount = 1;
  vp.scissorCount = 1;
  VkPipelineRasterizationStateCreateInfo rs{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
  rs.polygonMode = VK_POLYGON_MODE_FILL;
  rs.cullMode = VK_CULL_MODE_NONE;  // as the prepass
  rs.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
  rs.lineWidth = 1.0f;
  VkPipelineMultisampleStateCreateInfo ms{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
  ms.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
  VkPipelineDepthStencilStateCreateInfo ds{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
  ds.depthTestEnable = VK_TRUE;
  ds.depthWriteEnable = VK_FALSE;
  ds.depthCompareOp = VK_COMPARE_OP_EQUAL;  // only the fragment the prepass kept (thesis 4.4)
  VkPipelineColorBlendAttachmentState blend[2]{};
  blend[0].colorWriteMask = blend[1].colorWriteMask = 0xF;
  VkPipelineColorBlendStateCreateInfo cb{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  cb.attachmentCount = analysis ? 2 : 1;
  cb.pAttachments = blend;
  VkDynamicState dyn[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
  VkPipelineDynamicStateCreateInfo dy{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
  dy.dynamicStateCount = 2;
  dy.pDynamicStates = dyn;
  VkFormat formats[2] = {kHdrFormat, kRefNormalFormat};
  VkPipelineRenderingCreateInfo ri{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
  ri.colorAttachmentCount = analysis ? 2 : 1;
  ri.pColorAttachmentFormats = formats;
  ri.depthAttachmentFormat = kDepthFormat;
  VkGraphicsPipelineCreateInfo gi{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
  gi.pNext = &ri;
  gi.stageCount = 2;
  gi.pStages = stages;
  gi.pVertexInputState = &vi;
  gi.pInputAssemblyState = &ia;
  gi.pViewportState = &vp;
  gi.pRasterizationState = &rs;
  gi.pMultisampleState = &ms;
  gi.pDepthStencilState = &ds;
  gi.pColorBlendState = &cb;
  gi.pDynamicState = &dy;
  gi.layout = layout_.layout();
  VkPipeline pipeline = VK_NULL_HANDLE;
  VK_CHECK(vkCreateGraphicsPipelines(ctx_.device(), VK_NULL_HANDLE, 1, &gi, nullptr, &pipeline));
  return pipeline;
}

void ShadingPass::record(VkCommandBuffer cmd, const glm::mat4& viewProj, bool analysis) const {
  VkRenderingAttachmentInfo ca[2] = {{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO},
                                     {VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO}};
  const Image* targets[2] = {&color_, &refNormals_};
  for (int i = 0; i < 2; ++i) {
    ca[i].imageView = targets[i]->view();
    ca[i].imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    ca[i].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;  // sky: black, no normal
    ca[i].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    ca[i].clearValue.color = {{0.0f, 0.0f, 0.0f, i == 0 ? 1.0f : 0.0f}};  // opaque black sky; no normal
  }
  VkRenderingAttachmentInfo da{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  da.imageView = in_.depth->view();
  da.imageLayout = VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL;
  da.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
  da.storeOp = VK_ATTACHMENT_STORE_OP_NONE;
  VkRenderingInfo ri{VK_STRUCTURE_TYPE_RENDERING_INFO};
  ri.renderArea = {{0, 0}, {width_, height_}};
  ri.layerCount = 1;
  ri.colorAttachmentCount = analysis ? 2 : 1;
  ri.pColorAttachments = ca;
  ri.pDepthAttachment = &da;
  vkCmdBeginRendering(cmd, &ri);
  VkViewport viewport{0, 0, float(width_), float(height_), 0.0f, 1.0f};
  VkRect2D scissor{{0, 0}, {width_, height_}};
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &scissor);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, analysis ? analysis_ : timed_);
  VkDescriptorSet set = sets_.set();
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.layout(), 0, 1, &set, 0, nullptr);
  VkDeviceSize offset = 0;
  VkBuffer vb = scene_.vertices().handle();
  vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
  vkCmdBindIndexBuffer(cmd, scene_.indices().handle(), 0, VK_INDEX_TYPE_UINT32);
  for (const DrawItem& d : scene_.draws()) {
    gpu::DrawConstants dc{viewProj * d.model, d.model, d.material, d.firstIndex, d.vertexOffset, 0};
    vkCmdPushConstants(cmd, layout_.layout(), VK_SHADER_STAGE_ALL, 0, sizeof dc, &dc);
    vkCmdDrawIndexed(cmd, d.indexCount, 1, d.firstIndex, int32_t(d.vertexOffset), 0);
  }
  vkCmdEndRendering(cmd);
}

}  // namespace hb
