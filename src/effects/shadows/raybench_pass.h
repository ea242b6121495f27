// The ray throughput benchmark: re-traces exactly the shadow rays that the last analysis frame
// traced (shaders/shadows/raybench_common.glsl.inc) as a pure ray workload on the same TLAS, so that the
// shadow pass's ray rate can be held against the device's own rate on the same rays. Any backend
// traces them, whichever the frame used (`bvh`: our BVH, where the frame's shadows did not build on
// one; inputs.bvhNodes/bvhTriangles point into it).
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "effects/shadows/shadow_pass.h"
#include "gpu/rt_pipeline.h"
#include "gpu/trace_bvh.h"

namespace hb {

class RayBenchPass {
 public:
  RayBenchPass(const VulkanContext& ctx, RtBackend backend, uint32_t width, uint32_t height, const ShadowInputs& inputs,
               const ShadowPass& shadows, const TraceBvh* bvh = nullptr);
  ~RayBenchPass();
  void record(VkCommandBuffer cmd) const;
  // Per pixel (row-major) the number of its traced rays found unoccluded by the last record():
  // popcount(visibility & traced) over the pixel's walk words, what raybench_gpu_test checks bit
  // for bit. Sky pixels (no stored position) are never written: 0 unless an earlier frame had a
  // surface there (the image is cleared to 0 when the pass is built).
  std::vector<uint32_t> readResult() const;

 private:
  const VulkanContext& ctx_;
  RtBackend backend_;
  uint32_t width_, height_;
  Image result_;
  Pipeline compute_;
  std::unique_ptr<RaygenMissPipeline> rt_;
};

}  // namespace hb
