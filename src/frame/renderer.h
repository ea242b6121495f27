// The frame: a flat list of passes in frame order (design.md "The frame"), the resources they
// share, and per-pass GPU timestamps. Which passes run, and which resources exist, follow from the
// effects the scene calls for (planFrame); passesRun() and passesSkipped() say which and why.
#pragma once
#include <optional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "effects/effects.h"
#include "scene/camera.h"
#include "gpu/gpu_scene.h"
#include "gpu/gpu_timer.h"
#include "frame/passes/ambient_occlusion.h"
#include "frame/passes/depth_prepass.h"
#include "frame/passes/indirect.h"
#include "frame/passes/primary_3dr.h"
#include "gpu/accel.h"
#include "frame/passes/light_culling.h"
#include "frame/passes/shading.h"
#include "frame/passes/raybench.h"
#include "frame/passes/shadows.h"

namespace hb {

struct RenderSettings {
  uint32_t width = 1920;
  uint32_t height = 1080;
  uint32_t cameraIndex = 0;
  // The view's projection instead of the camera's own (config "projection"); empty: the camera's.
  std::optional<CameraProjection> projection;
  uint32_t tileSize = 16;
  bool lightCulling = true;
  bool aabb = false;
  // The effects asked for above the scene's own (config, --set); the frame is planned from them
  // and the scene (effects/effects.h planFrame). Empty: the scene's extras.effects or the defaults.
  EffectsRequest effects;
  std::string backend = "auto";        // auto | rayquery | pipeline
  uint32_t normals = 0;                // gpu::kNormalsOff / Naive / Improved
  uint32_t worldPos = 0;               // gpu::kWorldPosAlg41 / Matrix
  bool rangeTest = false;
  uint32_t depthSlices = 0;            // 0 off, 2..32: 2.5D slab test in light culling
  LightLists lightLists = LightLists::Tile;  // tile (capped at 32, the thesis) | bitmask | zbin
  bool scaledTMin = false;            // shadow t_min: false kShadowTMin, true max(that, kShadowTMinPerMetre·dist)
  std::string primary = "hardware";    // hardware (depth prepass) | 3dr | 3dr-binned | 2dr | raycast
  bool fp64Fallback = true;            // 3dr: false only to measure what the fallback prevents
  uint32_t r3dThreadBox = Raster3dPass::kDefaultSmallArea;  // 3dr: largest box one thread rasterizes
  bool visbufferShading = false;       // shading=visbuffer: in compute from the 3DR visibility buffer
  bool r3dShadingDepthTest = true;     // 3dr: early depth test before the id test (false: check only)
};

// Readbacks of the shadow pass (analysis frames).
struct ShadowReadback {
  uint32_t words = 1;                // visibility words per pixel
  // words × pixels, word-major (word j of pixel i at j·pixels + i): bit k of word j = the
  // (32j + k)-th light of the pixel's list walk (CullingReadback::pixelLights) is visible. Words past
  // the walk's last are left as the GPU found them.
  std::vector<uint32_t> visibility;
  std::vector<uint32_t> ranges;      // zbin: per pixel its bin range lo | hi << 16 (sorted lights); else empty
  std::vector<uint32_t> accounting;  // per pixel 4 words (gpu_types.h kAccount*)
  std::vector<float> normals;        // xyzw per pixel (w unused; zero = none)
  std::vector<float> positions;      // xyzw per pixel (w = 1 where not sky)
};

struct FrameTiming {
  double frameMs = 0;
  std::vector<std::pair<std::string, double>> passMs;  // in frame order
};

// The light lists as scene light indices, whatever form the GPU kept them in.
struct CullingReadback {
  LightLists lists = LightLists::Tile;
  uint32_t tilesX = 0, tilesY = 0;
  uint32_t capacity = 0;  // tile: lights stored per tile (32); masks: the scene's light count (no cap)
  // Per tile: its lights at indices[offset, offset + count) in the order the pixels walk them
  // (tile, bitmask: ascending scene index; zbin: ascending sorted index); total = lights that
  // touched the tile (> count: the tile overflowed, tile lists only).
  std::vector<uint32_t> offset, count, total;
  std::vector<uint32_t> indices;
  std::vector<uint32_t> sorted;  // zbin: per entry of indices, its sorted index (ascending in a tile)
  std::vector<uint32_t> order;   // zbin: sorted index -> scene light index
  std::vector<uint32_t> bins;    // zbin: kZBins ranges lo | hi << 16 over sorted indices
  // The slice [first, last) of indices a pixel of `tile` walks; range: the pixel's z-bin range
  // (ShadowReadback::ranges; ignored unless zbin).
  std::pair<uint32_t, uint32_t> pixelSlice(uint32_t tile, uint32_t range) const;
};

class Renderer {
 public:
  Renderer(const VulkanContext& ctx, const Scene& scene, const RenderSettings& settings);
  ~Renderer();

  // Records, submits and waits for one frame; returns its GPU timings. An analysis frame also
  // writes the shadow pass's accounting, normals and positions (never timed in a sweep).
  FrameTiming renderFrame(bool analysis = false);

  const glm::mat4& view() const { return view_; }
  const glm::mat4& proj() const { return proj_; }
  const Camera& camera() const { return camera_; }
  const RenderSettings& settings() const { return settings_; }
  const FramePlan& plan() const { return plan_; }
  const std::vector<std::string>& passesRun() const { return passesRun_; }
  const std::vector<std::pair<std::string, std::string>>& passesSkipped() const { return passesSkipped_; }
  bool hasCulling() const { return bool(culling_); }
  uint64_t listMemoryBytes() const { return culling_ ? culling_->memoryBytes() : 0; }  // grid, lists, bins
  bool hasShadows() const { return bool(shadows_); }
  const Raster3dPass* raster3d() const { return raster3d_.get(); }  // primary = 3dr only
  const AccelerationStructures* accel() const { return accel_.get(); }
  AoPass* ambientOcclusion() const { return ao_.get(); }  // when the effect runs
  IndirectPass* indirect() const { return indirect_.get(); }  // when the effect runs
  std::string backendUsed() const { return shadows_ ? toString(shadows_->settings().backend) : "none"; }

  // Ray throughput: re-traces the rays of the last analysis frame `repetitions` times as a pure
  // ray workload (passes/raybench.h); returns each repetition's GPU time in ms.
  // Precondition: hasShadows() and the last frame was an analysis frame.
  std::vector<double> rayBench(uint32_t repetitions);

  // Readbacks (analysis frames only).
  std::vector<float> readDepth() const;
  CullingReadback readCulling() const;
  ShadowReadback readShadows() const;
  std::vector<float> readColor() const;       // linear HDR RGBA per pixel
  std::vector<float> readRefNormals() const;  // analysis frames: true face normal xyz, w = 1 where valid

 private:
  const VulkanContext& ctx_;
  const Scene& scene_;
  RenderSettings settings_;
  FramePlan plan_;
  Camera camera_;
  glm::mat4 view_, proj_;
  GpuScene gpuScene_;
  Image depth_;
  VkSampler pointSampler_ = VK_NULL_HANDLE;
  Buffer frameConstants_, lights_;
  DepthPrepass depthPrepass_;
  std::unique_ptr<Raster3dPass> raster3d_;
  std::unique_ptr<LightCulling> culling_;
  std::unique_ptr<AccelerationStructures> accel_;
  std::unique_ptr<ShadowPass> shadows_;
  std::unique_ptr<AoPass> ao_;
  std::unique_ptr<IndirectPass> indirect_;
  std::unique_ptr<ShadingPass> shading_;
  std::unique_ptr<RayBenchPass> rayBench_;
  ShadowInputs shadowInputs_{};
  GpuTimer timer_;
  bool frustumsDone_ = false;
  std::vector<std::string> passesRun_;
  std::vector<std::pair<std::string, std::string>> passesSkipped_;
};

}  // namespace hb
