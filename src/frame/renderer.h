// The frame: the passes the plan runs, in frame order, each declaring what it reads and writes
// (frame/frame_pass.h), and per-pass GPU timestamps (docs/frame.md "The frame"). Which passes run,
// and which resources exist, follow from the effects the scene calls for (planFrame); the Renderer
// allocates the frame's shared resources, builds the base parts and the effects' parts in frame
// order, checks every pass's reads against what came before it, sizes the timer from the
// declarations and records the passes in one loop. passesRun() and passesSkipped() say which ran
// and why the others did not.
#pragma once
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "frame/frame_pass.h"
#include "frame/ray_backend.h"
#include "frame/render_settings.h"
#include "gpu/accel.h"
#include "gpu/gpu_scene.h"
#include "gpu/gpu_timer.h"
#include "gpu/trace_bvh.h"
#include "plan/effects.h"
#include "scene/camera.h"

namespace hb {

class Raster3dPass;

// Readbacks of the shadow pass (analysis frames).
struct ShadowReadback {
  uint32_t words = 1;  // visibility words per pixel
  // words × pixels, word-major (word j of pixel i at j·pixels + i): bit k of word j = the
  // (32j + k)-th light of the pixel's list walk (CullingReadback::pixelLights) is visible. Words past
  // the walk's last are left as the GPU found them.
  std::vector<uint32_t> visibility;
  std::vector<uint32_t> ranges;      // zbin: per pixel its bin range lo | hi << 16 (sorted lights); else empty
  std::vector<uint32_t> accounting;  // per pixel 4 words (gpu_types.h kAccount*)
  std::vector<float> normals;        // xyzw per pixel (w unused; zero = none)
  std::vector<float> positions;      // xyzw per pixel (w = 1 where not sky)
  // As visibility: bit k of word j = the pass traced a ray to the walk's (32j + k)-th light (words
  // past the walk's last are left as the GPU found them).
  std::vector<uint32_t> traced;
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
  // writes the passes' counters and readback images (never timed in a sweep).
  FrameTiming renderFrame(bool analysis = false);

  const VulkanContext& context() const { return ctx_; }
  const Scene& scene() const { return scene_; }
  const glm::mat4& view() const { return view_; }
  const glm::mat4& proj() const { return proj_; }
  const Camera& camera() const { return camera_; }
  const RenderSettings& settings() const { return settings_; }
  const FramePlan& plan() const { return plan_; }
  const std::vector<std::string>& passesRun() const { return passesRun_; }
  const std::vector<std::pair<std::string, std::string>>& passesSkipped() const { return passesSkipped_; }
  const FrameResources& resources() const { return resources_; }
  gpu::FrameConstants frameConstants() const;  // as the shaders read them
  // Every pass of the frame as it declared itself, in frame order.
  std::vector<const FramePass*> framePasses() const;
  // The part an effect built (by the effect's name), or a base part ("primary", "light_lists",
  // "shading"); null when it is not in this frame or is not a T.
  template <typename T>
  T* part(std::string_view name) const {
    for (const auto& [partName, p] : parts_)
      if (partName == name) return dynamic_cast<T*>(p.get());
    return nullptr;
  }
  // The frame's timer, for work timed outside the frame (a pass's micro-benchmark, say).
  GpuTimer& timer() { return *timer_; }

  bool hasCulling() const;
  uint64_t listMemoryBytes() const;      // grid, lists, bins; 0 without culling
  const Raster3dPass* raster3d() const;  // primary visibility by compute (raster3d, raycast) only
  const AccelerationStructures* accel() const { return accel_; }
  // backend=compute: our BVH, shared by every pass that traces (null otherwise).
  const TraceBvh* traceBvh() const { return tracer_.bvh; }
  // Which ray tracer the frame's ray passes use, and why (settings().backend is the one that ran).
  const BackendChoice& backendChoice() const { return tracer_.choice; }
  // The ray tracer every tracing pass takes; null when nothing in the frame traces.
  const RayTracer* rayTracer() const { return accel_ ? &tracer_ : nullptr; }

  // Readbacks (analysis frames only).
  std::vector<float> readDepth() const;
  CullingReadback readCulling() const;
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
  // The frame's shared resources, allocated when the plan needs them; then the parts, which may
  // hold references to them (declared after them: destroyed first).
  Image depth_;
  VkSampler pointSampler_ = VK_NULL_HANDLE;
  Buffer frameConstants_, lights_;
  // The frame's resources by name, and the keyed ones it owns: the acceleration structures and our
  // BVH that tracer_ points at, the LDM sets (built once per key, frame_pass.h FrameResources::build).
  FrameResources resources_;
  const AccelerationStructures* accel_ = nullptr;
  RayTracer tracer_;  // resolved once, when the frame traces
  std::vector<std::pair<std::string, std::unique_ptr<FramePart>>> parts_;
  std::vector<const FramePass*> order_;  // the plan's passes, in frame order
  // Each pass's declared accesses, resolved to the frame's buffers and images when its part was built
  // (a later part may replace an image under the same name).
  std::map<const FramePass*, std::vector<Use>> uses_;
  std::unique_ptr<GpuTimer> timer_;  // sized from the passes' declarations
  FrameTiming renderFrameOnce(bool analysis);
  bool onceDone_ = false;
  std::vector<std::string> passesRun_;
  std::vector<std::pair<std::string, std::string>> passesSkipped_;
};

}  // namespace hb
