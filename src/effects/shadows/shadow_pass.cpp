#include "effects/shadows/shadow_pass.h"

#include <cstring>
#include <vector>

#include "base/errors.h"
#include "frame/passes/depth_prepass.h"
#include "gpu/descriptor_binder.h"
#include "gpu/rt_pipeline.h"
#include "gpu/sync.h"
#include "shared/gpu_types.h"

namespace hb {

namespace {

// Visibility (or traced-ray) words: settings.visibilityWords per pixel, plus the z-bin range plane.
// One storage binding, so the device's maxStorageBufferRange bounds it; refused with what to lower.
VkDeviceSize visibilityBytes(const VulkanContext& ctx, const ShadowSettings& s, uint32_t width, uint32_t height,
                             const char* what) {
  const VkDeviceSize words = VkDeviceSize(s.visibilityWords) + (s.listMode == gpu::kListZbin ? 1 : 0);
  const VkDeviceSize bytes = words * width * height * sizeof(uint32_t);
  VkPhysicalDeviceProperties props;
  vkGetPhysicalDeviceProperties(ctx.physical(), &props);
  if (bytes > props.limits.maxStorageBufferRange)
    throw InputError("the shadow pass's " + std::string(what) + " words (" + std::to_string(words) + " a pixel at " +
                     std::to_string(width) + "x" + std::to_string(height) + ", " + std::to_string(bytes >> 20) +
                     " MiB) exceed device \"" + ctx.info().name + "\"'s storage buffer range of " +
                     std::to_string(props.limits.maxStorageBufferRange >> 20) +
                     " MiB; lower the resolution or light_count");
  return bytes;
}

}  // namespace

struct ShadowPass::Variant {
  Pipeline compute;                               // rayquery backend
  std::unique_ptr<RaygenMissPipeline> rtProgram;  // pipeline backend

  Variant(const VulkanContext& c, const ShadowSettings& s, const DescriptorBinder& binder, bool analysis) : compute(c) {
    SpecConstants spec{
        {s.tileSize, uint32_t(s.normals), uint32_t(s.worldPos), s.rangeTest ? 1u : 0u, analysis ? 1u : 0u, s.listMode}};
    if (s.backend == RtBackend::Compute)
      spec.values.insert(spec.values.end(), {s.bvhStack, s.bvhStackShared ? 1u : 0u, s.bvhWidth});
    if (s.backend != RtBackend::Pipeline) {
      compute.createCompute(binder, s.backend == RtBackend::Compute ? "shadows_compute.comp" : "shadows_rayquery.comp",
                            0, spec);
    } else {
      rtProgram = std::make_unique<RaygenMissPipeline>(c, binder, "shadows.rgen", "shadows.rmiss", spec);
    }
  }
  const Pipeline& pipeline() const { return rtProgram ? rtProgram->pipeline() : compute; }
};

ShadowPass::ShadowPass(const VulkanContext& ctx, const ShadowSettings& settings, uint32_t width, uint32_t height,
                       const ShadowInputs& in)
    : ctx_(ctx),
      settings_(settings),
      width_(width),
      height_(height),
      visibility_(ctx, visibilityBytes(ctx, settings, width, height, "visibility"),
                  VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT, false, MemClass::Images),
      traced_(ctx, visibilityBytes(ctx, settings, width, height, "traced-ray"),
              VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT, false, MemClass::Images),
      accounting_(ctx, width, height, VK_FORMAT_R32G32B32A32_UINT,
                  VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, VK_IMAGE_ASPECT_COLOR_BIT),
      normals_(ctx, width, height, VK_FORMAT_R32G32B32A32_SFLOAT,
               VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, VK_IMAGE_ASPECT_COLOR_BIT),
      positions_(ctx, width, height, VK_FORMAT_R32G32B32A32_SFLOAT,
                 VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, VK_IMAGE_ASPECT_COLOR_BIT) {
  if (settings.backend == RtBackend::RayQuery && !ctx.info().rayQuery)
    throw InputError("backend=rayquery: device \"" + ctx.info().name +
                     "\" has no VK_KHR_ray_query; use backend=pipeline or backend=auto");
  if (settings.backend == RtBackend::Pipeline && !ctx.info().rayTracingPipeline)
    throw InputError("backend=pipeline: device \"" + ctx.info().name +
                     "\" has no VK_KHR_ray_tracing_pipeline; use backend=rayquery or backend=auto");
  DescriptorBinder binder("shadows");
  binder.provide("Frame", *in.frameConstants);
  binder.provide("Lights", *in.lights);
  binder.provide("Grid", *in.grid);
  binder.provide("Indices", *in.indices);
  binder.provide("depthTex", *in.depth, depthReadLayout(*in.depth), in.sampler);
  if (settings.backend == RtBackend::Compute) {
    if (!ctx.info().shaderFloat64)
      throw DeviceError("backend=compute: device \"" + ctx.info().name +
                        "\" lacks shaderFloat64, which its watertight triangle test needs at exact zeros; use "
                        "backend=auto");
    HB_ASSERT(in.bvhNodes && in.bvhTriangles);
    binder.provide("BvhNodes", *in.bvhNodes);
    binder.provide("BvhTriangles", *in.bvhTriangles);
  } else {
    binder.provide("tlas", in.tlas);
  }
  const bool needsHits = settings.worldPos == WorldPosMethod::Hit || settings.normals == NormalCulling::Geometric;
  if (needsHits && !(in.hitIds && in.hitRays && in.hitTriangles))
    throw InputError(
        "world_pos=hit and normal_culling=geometric need the triangle ids of a computed primary "
        "visibility: set primary=3dr, 3dr-binned, 2dr or raycast");
  // Without them the Hit* bindings are never read; any buffer of the right type will do.
  binder.provide("HitIds", *(in.hitIds ? in.hitIds : in.lights));
  binder.provide("HitRays", *(in.hitRays ? in.hitRays : in.frameConstants));
  binder.provide("HitTriangles", *(in.hitTriangles ? in.hitTriangles : in.lights));
  binder.provide("Visibility", visibility_);
  binder.provide("Traced", traced_);
  binder.provide("accountingImage", accounting_, VK_IMAGE_LAYOUT_GENERAL);
  binder.provide("normalImage", normals_, VK_IMAGE_LAYOUT_GENERAL);
  binder.provide("positionImage", positions_, VK_IMAGE_LAYOUT_GENERAL);
  timed_ = std::make_unique<Variant>(ctx, settings, binder, false);
  analysis_ = std::make_unique<Variant>(ctx, settings, binder, true);
  binder.checkEveryNameRead();
  ctx.submitAndWait([&](VkCommandBuffer cmd) {  // the analysis images live in GENERAL
    Sync sync;
    sync.use(cmd, {{accounting_, access::kRayWrite.discarding()},
                   {normals_, access::kRayWrite.discarding()},
                   {positions_, access::kRayWrite.discarding()}});
  });
}

ShadowPass::~ShadowPass() = default;

void ShadowPass::record(VkCommandBuffer cmd, bool analysis) const {
  const Variant& v = analysis ? *analysis_ : *timed_;
  VkDescriptorSet set = v.pipeline().set();
  vkCmdBindPipeline(cmd, v.pipeline().bindPoint(), v.pipeline().handle());
  vkCmdBindDescriptorSets(cmd, v.pipeline().bindPoint(), v.pipeline().layout(), 0, 1, &set, 0, nullptr);
  if (settings_.backend != RtBackend::Pipeline) {
    const uint32_t t = settings_.tileSize;
    vkCmdDispatch(cmd, (width_ + t - 1) / t, (height_ + t - 1) / t, 1);
  } else {
    v.rtProgram->traceRays(cmd, width_, height_);
  }
}

}  // namespace hb
