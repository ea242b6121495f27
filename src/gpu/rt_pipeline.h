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
  // The layout and its set from the shaders' reflection (merged by name), written from `binder`.
  RaygenMissPipeline(const VulkanContext& ctx, const DescriptorBinder& binder, const std::string& raygen,
                     const std::string& miss, const SpecConstants& spec, const std::string& closestHit = "");
  // The shaders as `program` numbers their bindings, over `layout` (a set of that program's, shared
  // with other pipelines).
  RaygenMissPipeline(const VulkanContext& ctx, VkDescriptorSetLayout layout, const ShaderProgram& program,
                     const std::string& raygen, const std::string& miss, const SpecConstants& spec,
                     const std::string& closestHit = "");
  const Pipeline& pipeline() const { return pipeline_; }  // pipeline().set(): the binder's set
  void traceRays(VkCommandBuffer cmd, uint32_t width, uint32_t height) const;

 private:
  // The pipeline and its binding table from the shaders (their SPIR-V, in the order raygen, miss, hit).
  void create(const std::vector<std::vector<uint32_t>>& spirv, const SpecConstants& spec);
  const VulkanContext& ctx_;
  Pipeline pipeline_;
  Buffer sbt_;
  VkStridedDeviceAddressRegionKHR raygen_{}, miss_{}, hit_{}, callable_{};
};

}  // namespace hb
