#include "frame/passes/depth_prepass.h"

#include "base/errors.h"
#include "gpu/raster_pipeline.h"
#include "shared/gpu_types.h"

namespace hb {

DepthPrepass::DepthPrepass(const VulkanContext& ctx) : ctx_(ctx), pipeline_(ctx) {
  pipeline_.createLayout({}, sizeof(gpu::DrawConstants));
  ShaderModule vert(ctx, "depth.vert");
  RasterPipelineDesc desc;
  desc.layout = pipeline_.layout();
  desc.vertex = vert.handle();  // no fragment shader (thesis 4.1)
  desc.depthWrite = true;
  desc.depthCompare = VK_COMPARE_OP_GREATER_OR_EQUAL;  // reverse-Z: nearer = larger depth
  desc.depthFormat = kDepthFormat;
  pipeline_.pipeline_ = createRasterPipeline(ctx, desc);
  pipeline_.bindPoint_ = VK_PIPELINE_BIND_POINT_GRAPHICS;
}

DepthPrepass::~DepthPrepass() = default;

void DepthPrepass::record(VkCommandBuffer cmd, const GpuScene& scene, const glm::mat4& viewProj,
                          const Image& depth) const {
  VkRenderingAttachmentInfo da{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  da.imageView = depth.view();
  da.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
  da.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  da.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  da.clearValue.depthStencil = {0.0f, 0};  // reverse-Z: 0 is the far plane
  VkRenderingInfo ri{VK_STRUCTURE_TYPE_RENDERING_INFO};
  ri.renderArea = {{0, 0}, {depth.width(), depth.height()}};
  ri.layerCount = 1;
  ri.pDepthAttachment = &da;
  vkCmdBeginRendering(cmd, &ri);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.handle());
  drawScene(cmd, scene, pipeline_.layout(), viewProj, depth.width(), depth.height());
  vkCmdEndRendering(cmd);
}

}  // namespace hb
