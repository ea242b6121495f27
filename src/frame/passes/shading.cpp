#include "frame/passes/shading.h"

#include <algorithm>
#include <bit>
#include <string>
#include <utility>

#include <glm/gtc/matrix_inverse.hpp>

#include "base/errors.h"
#include "frame/passes/depth_prepass.h"
#include "gpu/descriptor_binder.h"
#include "gpu/raster_pipeline.h"
#include "gpu/sync.h"
#include "shared/gpu_types.h"

namespace hb {

ShadingPass::ShadingPass(const VulkanContext& ctx, const GpuScene& scene, uint32_t width, uint32_t height,
                         const ShadingInputs& in)
    : ctx_(ctx),
      scene_(scene),
      in_(in),
      width_(width),
      height_(height),
      textures_(ctx, scene.scene()),
      color_(ctx, width, height, kHdrFormat,
             VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                 (in.visbuffer ? VK_IMAGE_USAGE_STORAGE_BIT : 0),
             VK_IMAGE_ASPECT_COLOR_BIT),
      refNormals_(ctx, width, height, kRefNormalFormat,
                  VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                      (in.visbuffer ? VK_IMAGE_USAGE_STORAGE_BIT : 0),
                  VK_IMAGE_ASPECT_COLOR_BIT),
      dummyTermImage_(ctx, 1, 1, VK_FORMAT_R32G32B32A32_SFLOAT, VK_IMAGE_USAGE_STORAGE_BIT, VK_IMAGE_ASPECT_COLOR_BIT),
      dummyVisibility_(ctx, 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, MemClass::Other),
      layout_(ctx) {
  // What both shading shaders read (shading_bindings.glsl.inc); each pass's own follow.
  DescriptorBinder binder("shading");
  binder.provide("Frame", *in.frameConstants);
  binder.provide("Lights", *in.lights);
  // Without a culling pass the grid bindings are never read (USE_GRID = 0); any buffer will do.
  binder.provide("Grid", *(in.grid ? in.grid : in.lights));
  binder.provide("Indices", *(in.indices ? in.indices : in.lights));
  binder.provide("Visibility", *(in.visibility ? in.visibility : &dummyVisibility_));
  binder.provide("Materials", textures_.materials());
  binder.provide("Positions", scene.vertices());
  binder.provide("SceneIndices", scene.indices());
  // The effects' terms (shading_terms.glsl.inc): slot i reads its term's resource through the
  // binding of its storage; the other bindings of the slot, and every binding of an empty slot, are
  // never read (TERMi) and take a placeholder: any buffer, and a 1x1 RGBA32F image (the format matches).
  if (in.terms.size() > kMaxShadingTerms)
    throw InputError(std::to_string(in.terms.size()) + " effects add a term to shading, which composes at most " +
                     std::to_string(kMaxShadingTerms) + ": run fewer of them in one frame");
  for (uint32_t i = 0; i < kMaxShadingTerms; ++i) {
    const ShadingTermInput* t = i < in.terms.size() ? &in.terms[i] : nullptr;
    const auto storage = [&](ShadingTerm::Storage k) { return t && t->term.storage == k; };
    const std::string slot = std::to_string(i);
    binder.provide("TermFloats" + slot, storage(ShadingTerm::Storage::FloatPerPixel) ? *t->buffer : scene.indices());
    binder.provide("TermVec4s" + slot, storage(ShadingTerm::Storage::Vec4PerPixel) ? *t->buffer : scene.indices());
    binder.provide("termImage" + slot, storage(ShadingTerm::Storage::Rgba32fImage) ? *t->image : dummyTermImage_,
                   VK_IMAGE_LAYOUT_GENERAL);
  }
  binder.provide("textures", textures_.images(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, textures_.sampler());
  if (in.aa != AntiAliasing::None && !in.visbuffer && in.visibilityIds)
    throw InputError(std::string("aa=") + toString(in.aa) +
                     " after a compute primary needs shading=visbuffer (the forward pass draws one sample a pixel "
                     "after it): set shading=visbuffer");
  if (in.visbuffer) {
    if (!in.visibilityIds || !in.rays)
      throw InputError(
          "shading=visbuffer needs a visibility buffer of triangle ids: set primary=3dr, 3dr-binned, 2dr or "
          "raycast");
    createVisbuffer(ctx, binder);
  } else {
    // Without a visibility buffer VisibilityIds is never read (ID_MATCH = 0); any buffer will do.
    binder.provide("VisibilityIds", *(in.visibilityIds ? in.visibilityIds : &scene.indices()));
    layout_.createLayout(binder, ShaderProgram({"shading.vert", "shading.frag"}), sizeof(gpu::DrawConstants));
    if (in.aa != AntiAliasing::None) createMultisampled(ctx);
    timed_ = createPipeline(false);
    analysis_ = createPipeline(true);
  }
  binder.checkEveryNameRead();
  // The stand-in for indirect light is read, never written: into its layout once. The targets are
  // moved into theirs by the frame (the pass declares them).
  ctx.submitAndWait([&](VkCommandBuffer cmd) {
    Sync sync;
    sync.use(cmd, {{dummyTermImage_, access::kShaderRead.discarding()}});
  });
}

void ShadingPass::createMultisampled(const VulkanContext& ctx) {
  if (in_.aa == AntiAliasing::Csaa4x12)
    throw InputError(
        "aa=csaa-4-12 is 3D rasterization's (its coverage samples are tested in compute); the raster pipeline "
        "multisamples with MSAA only: set aa=msaa4, msaa8 or msaa16 with primary=hardware, or a compute primary");
  const uint32_t n = aaStoredSamples(in_.aa);
  samples_ = VkSampleCountFlagBits(n);
  VkPhysicalDeviceProperties props;
  vkGetPhysicalDeviceProperties(ctx.physical(), &props);
  const VkSampleCountFlags supported =
      props.limits.framebufferColorSampleCounts & props.limits.framebufferDepthSampleCounts;
  if (!(supported & samples_)) {
    std::string list;
    for (uint32_t c = 1; c <= 64; c *= 2)
      if (supported & c) list += (list.empty() ? "" : ", ") + std::to_string(c);
    throw DeviceError("device \"" + ctx.info().name + "\" cannot multisample " + std::to_string(n) +
                      " times in the raster pipeline (colour and depth targets take " + list +
                      " samples): pick one of those with aa=msaaN, or a compute primary with shading=visbuffer");
  }
  // Resolved in the pass itself: the samples never leave the chip where the device keeps them there.
  const VkImageUsageFlags transient = VK_IMAGE_USAGE_TRANSIENT_ATTACHMENT_BIT;
  msColor_ = Image(ctx, width_, height_, kHdrFormat, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | transient,
                   VK_IMAGE_ASPECT_COLOR_BIT, 1, MemClass::Images, samples_);
  msRefNormals_ = Image(ctx, width_, height_, kRefNormalFormat, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | transient,
                        VK_IMAGE_ASPECT_COLOR_BIT, 1, MemClass::Images, samples_);
  msDepth_ = Image(ctx, width_, height_, kDepthFormat, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | transient,
                   VK_IMAGE_ASPECT_DEPTH_BIT, 1, MemClass::Images, samples_);
  // The depth of every sample first (depth.vert, no fragment shader, colour declared but not written),
  // so that the shading draw shades each pixel's visible triangles once (EQUAL), as without MSAA.
  ShaderModule vert(ctx, "depth.vert");
  RasterPipelineDesc desc;
  desc.layout = layout_.layout();
  desc.vertex = vert.handle();
  desc.depthWrite = true;
  desc.depthCompare = VK_COMPARE_OP_GREATER_OR_EQUAL;
  desc.depthFormat = kDepthFormat;
  desc.colorFormats = {kHdrFormat, kRefNormalFormat};
  desc.colorWrites = false;
  desc.samples = samples_;
  msDepthPipeline_ = createRasterPipeline(ctx, desc);
  // The sample targets live in their attachment layouts (cleared by every frame's pass).
  ctx.submitAndWait([&](VkCommandBuffer cmd) {
    Sync sync;
    sync.use(cmd, {{msColor_, access::kColorAttachment.discarding()},
                   {msRefNormals_, access::kColorAttachment.discarding()},
                   {msDepth_, access::kDepthAttachment.discarding()}});
  });
}

ShadingPass::~ShadingPass() {
  if (msDepthPipeline_) vkDestroyPipeline(ctx_.device(), msDepthPipeline_, nullptr);
  if (timed_) vkDestroyPipeline(ctx_.device(), timed_, nullptr);
  if (analysis_) vkDestroyPipeline(ctx_.device(), analysis_, nullptr);
}

SpecConstants ShadingPass::withTerms(std::vector<uint32_t> values) const {
  constexpr uint32_t kFirstTermId = 16;  // shading_terms.glsl.inc; the ids between are unused
  HB_ASSERT(values.size() <= kFirstTermId);
  values.resize(kFirstTermId, 0u);
  for (uint32_t i = 0; i < kMaxShadingTerms; ++i) {
    if (i >= in_.terms.size()) {
      values.insert(values.end(), {0u, 0u, 0u, 0u, 0u});  // TERMi = 0: no term in slot i
      continue;
    }
    const ShadingTerm& t = in_.terms[i].term;
    values.push_back(uint32_t(t.storage) | (t.weight == ShadingTerm::Weight::AsIs ? 4u : 0u));  // kTermAsIs
    for (float f : {t.scale[0], t.scale[1], t.scale[2], t.none}) values.push_back(std::bit_cast<uint32_t>(f));
  }
  return SpecConstants{std::move(values)};
}

VkPipeline ShadingPass::createPipeline(bool analysis) {
  const ShaderProgram program({"shading.vert", "shading.frag"});  // the numbers of layout_'s set
  ShaderModule vert(ctx_, program.spirv(0)), frag(ctx_, program.spirv(1));
  SpecConstants spec = withTerms({in_.tileSize, in_.grid ? 1u : 0u, in_.visibility ? 1u : 0u, analysis ? 1u : 0u,
                                  in_.visibilityIds ? 1u : 0u, in_.listMode, in_.visibilityWords <= 1 ? 1u : 0u,
                                  in_.perspective ? 1u : 0u});
  std::vector<VkSpecializationMapEntry> entries;
  VkSpecializationInfo si = specializationInfo(spec, entries);
  RasterPipelineDesc desc;
  desc.layout = layout_.layout();
  desc.vertex = vert.handle();
  desc.fragment = frag.handle();
  desc.fragmentSpec = &si;
  desc.vertexAttributes = 3;
  desc.depthWrite = false;
  // Only the fragment the prepass kept (thesis 4.4). After 3D rasterization the id test decides;
  // the depth test (early, as the shader writes no depth) only removes the fragments that lie
  // clearly behind: the fragment's depth is moved towards the eye by kIdMatchDepthBias units of
  // the primitive's largest depth exponent (2^(e-23) for D32F) plus its depth slope, far more
  // than the two rasterizers' rounding difference of a few u, so the visible triangle always
  // passes. Raster3dTest.On3drEarlyDepthTestShadesExactlyWhatTheIdTestAloneShades checks it
  // (with the bias set to 0 in a local build, 5,235 of 14,400 atrium pixels at 160x90 lost their
  // fragment on lavapipe).
  constexpr float kIdMatchDepthBias = 64.0f;
  desc.depthCompare = VK_COMPARE_OP_EQUAL;
  if (in_.visibilityIds) {
    desc.depthCompare = in_.idMatchDepthTest ? VK_COMPARE_OP_GREATER_OR_EQUAL : VK_COMPARE_OP_ALWAYS;
    desc.depthBiasConstant = in_.idMatchDepthTest ? kIdMatchDepthBias : 0.0f;
    desc.depthBiasSlope = in_.idMatchDepthTest ? 1.0f : 0.0f;
  }
  desc.colorFormats = {kHdrFormat};
  if (analysis || msDepthPipeline_) desc.colorFormats.push_back(kRefNormalFormat);
  desc.depthFormat = kDepthFormat;
  if (msDepthPipeline_) {
    // MSAA: the multisampled depth of this pass's own depth draw, bit for bit (invariant gl_Position).
    desc.samples = samples_;
    desc.depthCompare = VK_COMPARE_OP_EQUAL;
  }
  return createRasterPipeline(ctx_, desc);
}

void ShadingPass::createVisbuffer(const VulkanContext& ctx, DescriptorBinder& binder) {
  const DrawTables tables = drawTables(scene_);
  const std::vector<gpu::GpuDraw>& draws = tables.draws;
  const std::vector<uint32_t>& triangleDraw = tables.triangleDraw;
  draws_ = uploadBuffer(ctx, draws.data(), draws.size() * sizeof(gpu::GpuDraw), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                        MemClass::Geometry);
  triangleDraw_ = uploadBuffer(ctx, triangleDraw.data(), std::max<size_t>(1, triangleDraw.size()) * sizeof(uint32_t),
                               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemClass::Geometry);
  binder.provide("VisibilityIds", *in_.visibilityIds);
  binder.provide("Rays", *in_.rays);
  binder.provide("Draws", draws_);
  binder.provide("TriangleDraws", triangleDraw_);
  binder.provide("colorImage", color_, VK_IMAGE_LAYOUT_GENERAL);
  binder.provide("refNormalImage", refNormals_, VK_IMAGE_LAYOUT_GENERAL);
  vbTimed_ = std::make_unique<Pipeline>(ctx);
  vbAnalysis_ = std::make_unique<Pipeline>(ctx);
  for (auto [p, analysis] : {std::pair{vbTimed_.get(), 0u}, std::pair{vbAnalysis_.get(), 1u}}) {
    p->createCompute(binder, "shading_visbuffer.comp", 0,
                     withTerms({in_.tileSize, in_.grid ? 1u : 0u, in_.visibility ? 1u : 0u, analysis, in_.listMode,
                                in_.visibilityWords <= 1 ? 1u : 0u, aaStoredSamples(in_.aa),
                                in_.aa == AntiAliasing::Csaa4x12 ? 1u : 0u, in_.planeStride}));
  }
}

void ShadingPass::recordVisbuffer(VkCommandBuffer cmd, bool analysis) const {
  const Pipeline& p = analysis ? *vbAnalysis_ : *vbTimed_;
  VkDescriptorSet set = p.set();
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.handle());
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.layout(), 0, 1, &set, 0, nullptr);
  vkCmdDispatch(cmd, (width_ + 7) / 8, (height_ + 7) / 8, 1);
}

void ShadingPass::record(VkCommandBuffer cmd, const glm::mat4& viewProj, bool analysis) const {
  if (visbuffer()) {
    recordVisbuffer(cmd, analysis);
    return;
  }
  VkRenderingAttachmentInfo ca[2] = {{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO},
                                     {VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO}};
  const Image* targets[2] = {&color_, &refNormals_};
  const bool ms = msDepthPipeline_ != VK_NULL_HANDLE;
  const Image* msTargets[2] = {&msColor_, &msRefNormals_};
  for (int i = 0; i < 2; ++i) {
    ca[i].imageView = targets[i]->view();
    ca[i].imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    ca[i].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;  // sky: black, no normal
    ca[i].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    ca[i].clearValue.color = {{0.0f, 0.0f, 0.0f, i == 0 ? 1.0f : 0.0f}};  // opaque black sky; no normal
    if (ms) {  // the samples, averaged into the single-sample target at the end of the pass
      ca[i].imageView = msTargets[i]->view();
      ca[i].storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
      ca[i].resolveMode = VK_RESOLVE_MODE_AVERAGE_BIT;
      ca[i].resolveImageView = targets[i]->view();
      ca[i].resolveImageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    }
  }
  // A timed frame writes no normals: the pipelines declare the target, the frame discards it.
  if (ms && !analysis) ca[1] = {VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  VkRenderingAttachmentInfo da{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  da.imageView = in_.depth->view();
  da.imageLayout = VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL;
  da.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
  da.storeOp = VK_ATTACHMENT_STORE_OP_NONE;
  if (ms) {
    da.imageView = msDepth_.view();
    da.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    da.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    da.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    da.clearValue.depthStencil = {0.0f, 0};  // reverse-Z: 0 is the far plane
  }
  VkRenderingInfo ri{VK_STRUCTURE_TYPE_RENDERING_INFO};
  ri.renderArea = {{0, 0}, {width_, height_}};
  ri.layerCount = 1;
  ri.colorAttachmentCount = analysis || ms ? 2 : 1;
  ri.pColorAttachments = ca;
  ri.pDepthAttachment = &da;
  vkCmdBeginRendering(cmd, &ri);
  if (ms) {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, msDepthPipeline_);
    drawScene(cmd, scene_, layout_.layout(), viewProj, width_, height_);
  }
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, analysis ? analysis_ : timed_);
  VkDescriptorSet set = layout_.set();
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.layout(), 0, 1, &set, 0, nullptr);
  drawScene(cmd, scene_, layout_.layout(), viewProj, width_, height_);
  vkCmdEndRendering(cmd);
}

}  // namespace hb
