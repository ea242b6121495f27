// The shadows effect in the frame: the shadow pass ("shadows", shadow_pass.h) built from the light
// lists, the depth and the ray tracer's scene, publishing its visibility words for shading; its
// readbacks; and the ray-throughput benchmark on the same rays (raybench_pass.h).
#pragma once
#include <memory>
#include <vector>

#include "effects/shadows/raybench_pass.h"
#include "effects/shadows/shadow_pass.h"
#include "frame/frame_builder.h"
#include "frame/passes/trace_bvh.h"
#include "frame/renderer.h"

namespace hb {

inline constexpr const char* kShadowsPass = "shadows";

class ShadowsPart : public FramePart {
 public:
  explicit ShadowsPart(FrameBuilder& frame);
  const ShadowPass& shadowPass() const { return *shadows_; }
  ShadowReadback readShadows() const;  // after an analysis frame
  // Re-traces the rays of the last analysis frame `repetitions` times as a pure ray workload;
  // returns each repetition's GPU time in ms. Precondition: the last frame was an analysis frame.
  std::vector<double> rayBench(GpuTimer& timer, uint32_t repetitions);
  // Per pixel the traced rays the last rayBench() repetition found visible (RayBenchPass::readResult).
  // Precondition: rayBench() has run (with repetitions >= 1 since the rays last changed).
  std::vector<uint32_t> readRayBench() const;
  // backend=compute: our BVH (render.json "compute_bvh"); empty otherwise.
  const TraceBvh& computeBvh() const { return bvh_; }

 private:
  const VulkanContext& ctx_;
  uint32_t width_, height_;
  ShadowInputs inputs_{};
  TraceBvh bvh_;  // backend=compute
  std::unique_ptr<ShadowPass> shadows_;
  std::unique_ptr<RayBenchPass> rayBench_;
};

// The frame's shadows part; null when the effect does not run.
ShadowsPart* shadowsOf(const Renderer& renderer);
std::unique_ptr<FramePart> buildShadows(FrameBuilder& frame);

}  // namespace hb
