// A ray-tracing pipeline of one ray-generation and one miss shader and, optionally, one triangle
// hit group with a closest-hit shader (shadow rays have none: they skip closest-hit shaders and all
// geometry is opaque; primary rays use one), with its shader binding table.
#pragma once
#include <string>

#include "gpu/vk_pipeline.h"
#include "gpu/vk_resources.h"

namespace hb {

class RaygenMissPipeline {
 public:
  // Precondition: ctx.info().rayTracingPipeline. spec applies to the ray-generation and closest-hit
  // shaders; closestHit empty: no hit group.
  RaygenMissPipeline(const VulkanContext& ctx, VkDescriptorSetLayout layout, const std::string& raygen,
                     const std::string& miss, const SpecConstants& spec, const std::string& closestHit = "");
  const Pipeline& pipeline() const { return pipeline_; }
  void traceRays(VkCommandBuffer cmd, uint32_t width, uint32_t height) const;

 private:
  const VulkanContext& ctx_;
  Pipeline pipeline_;
  Buffer sbt_;
  VkStridedDeviceAddressRegionKHR raygen_{}, miss_{}, hit_{}, callable_{};
};

}  // namespace hb
