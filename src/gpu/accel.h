// Acceleration structures for ray-traced effects: one BLAS per mesh (its primitives as opaque
// triangle geometries) and one TLAS over the scene's instances. Built only when an effect needs
// rays (the renderer decides); the build time and the bytes are reported.
#pragma once
#include <vector>

#include "gpu/gpu_scene.h"
#include "gpu/vk_resources.h"

namespace hb {

class AccelerationStructures {
 public:
  // Precondition: ctx.info().accelerationStructure.
  AccelerationStructures(const VulkanContext& ctx, const GpuScene& scene);
  ~AccelerationStructures();
  AccelerationStructures(const AccelerationStructures&) = delete;

  VkAccelerationStructureKHR tlas() const { return tlas_; }
  double buildMs() const { return buildMs_; }  // wall-clock time of the builds (submit to fence)
  uint64_t bytes() const { return bytes_; }    // BLAS + TLAS storage
  uint32_t blasCount() const { return uint32_t(blas_.size()); }
  // Builds since the process started (every constructor), for tests that count a frame's builds.
  static uint64_t buildCount();

 private:
  const VulkanContext& ctx_;
  std::vector<VkAccelerationStructureKHR> blas_;
  std::vector<Buffer> blasBuffers_;
  VkAccelerationStructureKHR tlas_ = VK_NULL_HANDLE;
  Buffer tlasBuffer_, instances_;
  double buildMs_ = 0;
  uint64_t bytes_ = 0;
};

}  // namespace hb
