// The base frame's parts, which every frame has whatever effects run (docs/frame.md "The frame"):
//   primary visibility  the hardware depth prepass, or raster3d / raycast in compute
//                       (frame/passes/raster3d.h), writing "depth" (and "visibility");
//   light lists         tile frustums once, then light culling every frame, when some light can
//                       be culled into tiles;
//   shading             direct light through the lists, with the shadow pass's visibility, plus the
//                       terms the effects before it declared (frame_pass.h ShadingTerm).
#pragma once
#include <memory>
#include <vector>

#include "frame/frame_builder.h"
#include "frame/frame_pass.h"
#include "frame/passes/depth_prepass.h"
#include "frame/passes/light_culling.h"
#include "frame/passes/raster3d.h"
#include "frame/passes/shading.h"

namespace hb {

// What the shadow pass publishes for shading's light loop (optional). What effects add to the
// light they declare as terms (FrameResources::addShadingTerm) under names of their own.
namespace res {
inline constexpr const char* kShadowVisibility = "shadows.visibility";  // words per pixel: lights visible
}  // namespace res

class PrimaryPart : public FramePart {
 public:
  explicit PrimaryPart(FrameBuilder& frame);
  const Raster3dPass* raster3d() const { return raster3d_.get(); }  // primary = 3dr, 3dr-binned, 2dr, raycast
  bool afterFrame() override;  // the 3DR work list grows to what the frame asked for

 private:
  std::unique_ptr<DepthPrepass> prepass_;
  std::unique_ptr<Raster3dPass> raster3d_;
};

class LightListsPart : public FramePart {
 public:
  explicit LightListsPart(FrameBuilder& frame);
  void recordOnce(VkCommandBuffer cmd, Sync& sync) const override;  // the tile frustums
  const LightCulling& culling() const { return *culling_; }

 private:
  std::unique_ptr<LightCulling> culling_;
};

class ShadingPart : public FramePart {
 public:
  explicit ShadingPart(FrameBuilder& frame);
  const ShadingPass& shading() const { return *shading_; }

 private:
  std::unique_ptr<ShadingPass> shading_;
};

}  // namespace hb
