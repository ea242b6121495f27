// Pass 5 (thesis 4.4): the forward shading pass — the scene drawn again with depth test EQUAL
// against the prepass depth (writes off; after 3D rasterization: the visibility buffer's id instead), Cook-Torrance
// with bindless textures, visibility from the shadow pass's bitmask. Writes a linear HDR colour target (RGBA16F); the
// analysis variant also writes each pixel's true face normal (the reference for normal reconstruction).
#pragma once
#include <memory>
#include <vector>

#include "config/config.h"
#include "frame/frame_pass.h"
#include "gpu/gpu_scene.h"
#include "gpu/gpu_textures.h"
#include "gpu/vk_pipeline.h"

namespace hb {

// The most terms one frame's shading adds (shaders/shading_terms.glsl.inc has a slot for each).
constexpr uint32_t kMaxShadingTerms = 4;

// A declared term (frame_pass.h ShadingTerm) with its resource: `buffer` for the per-pixel
// storages, `image` (RGBA32F, GENERAL layout) for Rgba32fImage.
struct ShadingTermInput {
  ShadingTerm term;
  const Buffer* buffer = nullptr;
  const Image* image = nullptr;
};

struct ShadingInputs {
  const Buffer* frameConstants;
  const Buffer* lights;
  const Buffer* grid;        // nullptr: no culling pass ran (every pixel loops over every light)
  const Buffer* indices;     // nullptr with grid
  const Buffer* visibility;  // nullptr: no shadow pass (every light visible); ShadowPass::visibility()
  const Image* depth;        // DEPTH_READ_ONLY_OPTIMAL
  uint32_t tileSize;
  uint32_t listMode;  // gpu::kList*: how grid and indices hold the tile lists
  // 3D rasterization's visibility buffer (uint64 per pixel: t bits << 32 | triangle id), or
  // nullptr after the hardware prepass. Given: no depth test; a fragment is shaded only where its
  // triangle is the pixel's (the depths of two rasterizers differ in their last bits, so EQUAL
  // cannot be used).
  const Buffer* visibilityIds = nullptr;
  // With visibilityIds: an early depth test (biased towards the eye) before the id test; false
  // shades every fragment up to the id test (only to check that the two agree).
  bool idMatchDepthTest = true;
  // With visibilityIds: shade in compute from the visibility buffer (no second rasterization);
  // needs the 3DR ray constants.
  bool visbuffer = false;
  const Buffer* rays = nullptr;
  // What the effects before shading add, in declaration order (at most kMaxShadingTerms: InputError).
  std::vector<ShadingTermInput> terms;
  // Visibility words per pixel the shadow pass writes (1 for tile lists or at most 32 lights):
  // with 1 the word is read once before the light walk (a specialisation constant).
  uint32_t visibilityWords = 1;
  // A perspective view: the view vector needs no orthographic branch (a specialisation constant).
  bool perspective = true;
  // Anti-aliasing (docs/methods/3d-rasterization.md "Anti-aliasing"). Visbuffer: the visibility
  // buffer's sample planes (Raster3dPass::planes() − 1 of them, planeStride apart) resolved per
  // distinct triangle; forward (the hardware path): the raster pipeline's own multisampling, a
  // multisampled depth pass and the shading pass into multisampled targets resolved to color().
  AntiAliasing aa = AntiAliasing::None;
  uint32_t planeStride = 0;
};

constexpr VkFormat kHdrFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
constexpr VkFormat kRefNormalFormat = VK_FORMAT_R32G32B32A32_SFLOAT;

class DescriptorBinder;

class ShadingPass {
 public:
  ShadingPass(const VulkanContext& ctx, const GpuScene& scene, uint32_t width, uint32_t height,
              const ShadingInputs& inputs);
  ~ShadingPass();
  void record(VkCommandBuffer cmd, const glm::mat4& viewProj, bool analysis) const;
  bool visbuffer() const { return bool(vbTimed_); }
  const Image& color() const { return color_; }  // COLOR_ATTACHMENT_OPTIMAL after record
  const Image& refNormals() const { return refNormals_; }

 private:
  VkPipeline createPipeline(bool analysis);
  // The terms' specialisation constants (ids 16 and after) appended to a shader's own.
  SpecConstants withTerms(std::vector<uint32_t> values) const;
  void createMultisampled(const VulkanContext& ctx);
  void createVisbuffer(const VulkanContext& ctx, DescriptorBinder& binder);
  void recordVisbuffer(VkCommandBuffer cmd, bool analysis) const;
  const VulkanContext& ctx_;
  const GpuScene& scene_;
  ShadingInputs in_;
  uint32_t width_, height_;
  GpuTextures textures_;
  Image color_, refNormals_, dummyTermImage_;
  // Hardware MSAA: the multisampled targets and the depth-only pipeline that fills msDepth_.
  Image msColor_, msRefNormals_, msDepth_;
  VkPipeline msDepthPipeline_ = VK_NULL_HANDLE;
  VkSampleCountFlagBits samples_ = VK_SAMPLE_COUNT_1_BIT;
  Buffer dummyVisibility_;
  Pipeline layout_;  // the forward pass's layout and set (shading.vert + shading.frag)
  VkPipeline timed_ = VK_NULL_HANDLE, analysis_ = VK_NULL_HANDLE;
  // Visibility-buffer shading (in_.visbuffer): its draws, triangle-to-draw table and pipelines.
  Buffer draws_, triangleDraw_;
  std::unique_ptr<Pipeline> vbTimed_, vbAnalysis_;
};

}  // namespace hb
