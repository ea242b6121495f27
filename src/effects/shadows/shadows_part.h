// The shadows effect in the frame: the shadow pass ("shadows", shadow_pass.h) built from the light
// lists, the depth and the ray tracer's scene, publishing its visibility words for shading; its
// readbacks; and the ray-throughput benchmark on the same rays (raybench_pass.h).
#pragma once
#include <memory>
#include <optional>
#include <vector>

#include "effects/shadows/raybench_pass.h"
#include "effects/shadows/shadow_pass.h"
#include "frame/frame_builder.h"
#include "frame/renderer.h"
#include "gpu/trace_bvh.h"

namespace hb {

inline constexpr const char* kShadowsPass = "shadows";

class ShadowsPart : public FramePart {
 public:
  explicit ShadowsPart(FrameBuilder& frame);
  const ShadowPass& shadowPass() const { return *shadows_; }
  ShadowReadback readShadows() const;  // after an analysis frame
  // Re-traces the rays of the last analysis frame `repetitions` times as a pure ray workload,
  // through `backend` (default: the frame's); returns each repetition's GPU time in ms.
  // Precondition: the last frame was an analysis frame.
  std::vector<double> rayBench(GpuTimer& timer, uint32_t repetitions, std::optional<RtBackend> backend = {});
  // The backends raybench can trace on this device, the frame's first (sweep: "raybench.backends").
  std::vector<RtBackend> rayBenchBackends() const;
  // Per pixel the traced rays the last rayBench() repetition through `backend` found visible
  // (RayBenchPass::readResult). Precondition: rayBench() has run through it.
  std::vector<uint32_t> readRayBench(std::optional<RtBackend> backend = {}) const;

 private:
  const VulkanContext& ctx_;
  const Scene& scene_;
  uint32_t width_, height_;
  uint32_t bvhWidth_;          // bvh_width: raybench's BVH, where the frame has none
  FrameResources& resources_;  // the frame's: raybench through compute asks it for our BVH (keyed)
  ShadowInputs inputs_{};
  std::unique_ptr<ShadowPass> shadows_;
  std::unique_ptr<RayBenchPass> rayBenches_[4];  // by RtBackend (never Auto)
};

// The frame's shadows part; null when the effect does not run.
ShadowsPart* shadowsOf(const Renderer& renderer);
std::unique_ptr<FramePart> buildShadows(FrameBuilder& frame);

}  // namespace hb
