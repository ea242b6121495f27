// The frame: a flat list of passes in frame order (design.md "The frame"), the resources they
// share, and per-pass GPU timestamps. Timed frames record only the passes; analysis frames (not
// timed) add counters and readbacks.
#pragma once
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "camera.h"
#include "gpu_scene.h"
#include "gpu_timer.h"
#include "passes/depth_prepass.h"

namespace hb {

struct RenderSettings {
  uint32_t width = 1920;
  uint32_t height = 1080;
  uint32_t cameraIndex = 0;
};

struct FrameTiming {
  double frameMs = 0;
  std::vector<std::pair<std::string, double>> passMs;  // in frame order
};

class Renderer {
 public:
  Renderer(const VulkanContext& ctx, const Scene& scene, const RenderSettings& settings);
  ~Renderer();

  // Records, submits and waits for one frame; returns its GPU timings.
  FrameTiming renderFrame();

  const glm::mat4& view() const { return view_; }
  const glm::mat4& proj() const { return proj_; }
  const Camera& camera() const { return camera_; }
  const std::vector<std::string>& passesRun() const { return passesRun_; }

  // Readbacks (analysis only).
  std::vector<float> readDepth() const;

 private:
  const VulkanContext& ctx_;
  RenderSettings settings_;
  Camera camera_;
  glm::mat4 view_, proj_;
  GpuScene gpuScene_;
  Image depth_;
  DepthPrepass depthPrepass_;
  GpuTimer timer_;
  std::vector<std::string> passesRun_;
};

}  // namespace hb
