#include "effects/shadows/shadow_pass.h"

#include <cstring>
#include <vector>

#include "base/errors.h"
#include "gpu/rt_pipeline.h"
#include "gpu/sync.h"
#include "shared/bindings.h"
#include "shared/gpu_types.h"

namespace hb {

const char* toString(ShadowBackend b) {
  switch (b) {
    case ShadowBackend::RayQuery: return "rayquery";
    case ShadowBackend::Pipeline: return "pipeline";
    case ShadowBackend::Compute: return "compute";
  }
  return "?";
}

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

std::vector<Binding> shadowBindings(ShadowBackend backend, VkShaderStageFlags stages) {
  std::vector<Binding> b = {{HB_SURFACE_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, stages},
                            {HB_SHADOW_LIGHTS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, stages},
                            {HB_SHADOW_GRID, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, stages},
                            {HB_SHADOW_INDICES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, stages},
                            {HB_SURFACE_DEPTH, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, stages},
                            {HB_SURFACE_TLAS, VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR, stages},
                            {HB_SHADOW_VISIBILITY, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, stages},
                            {HB_SHADOW_ACCOUNTING, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, stages},
                            {HB_SHADOW_NORMALS, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, stages},
                            {HB_SHADOW_POSITIONS, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, stages},
                            {HB_SHADOW_TRACED, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, stages},
                            {HB_SURFACE_HIT_IDS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, stages},
                            {HB_SURFACE_HIT_RAYS, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, stages},
                            {HB_SURFACE_HIT_TRIANGLES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, stages}};
  if (backend == ShadowBackend::Compute) {  // our BVH instead of the TLAS
    std::erase_if(b, [](const Binding& x) { return x.binding == HB_SURFACE_TLAS; });
    b.push_back({HB_SURFACE_BVH_NODES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, stages});
    b.push_back({HB_SURFACE_BVH_TRIANGLES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, stages});
  }
  return b;
}

VkShaderStageFlags stagesFor(ShadowBackend b) {
  return b != ShadowBackend::Pipeline ? VK_SHADER_STAGE_COMPUTE_BIT
                                      : VK_SHADER_STAGE_RAYGEN_BIT_KHR | VK_SHADER_STAGE_MISS_BIT_KHR;
}

}  // namespace

struct ShadowPass::Variant {
  Pipeline compute;                               // rayquery backend
  std::unique_ptr<RaygenMissPipeline> rtProgram;  // pipeline backend

  Variant(const VulkanContext& c, const ShadowSettings& s, VkDescriptorSetLayout layout, bool analysis) : compute(c) {
    SpecConstants spec{
        {s.tileSize, uint32_t(s.normals), uint32_t(s.worldPos), s.rangeTest ? 1u : 0u, analysis ? 1u : 0u, s.listMode}};
    if (s.backend == ShadowBackend::Compute)
      spec.values.insert(spec.values.end(), {s.bvhStack, s.bvhStackShared ? 1u : 0u, s.bvhWidth});
    if (s.backend != ShadowBackend::Pipeline) {
      compute.createLayout({layout}, 0);
      compute.createCompute(s.backend == ShadowBackend::Compute ? "shadows_compute.comp" : "shadows_rayquery.comp",
                            spec);
    } else {
      rtProgram = std::make_unique<RaygenMissPipeline>(c, layout, "shadows.rgen", "shadows.rmiss", spec);
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
                 VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, VK_IMAGE_ASPECT_COLOR_BIT),
      sets_(ctx, shadowBindings(settings.backend, stagesFor(settings.backend))) {
  if (settings.backend == ShadowBackend::RayQuery && !ctx.info().rayQuery)
    throw InputError("backend=rayquery: device \"" + ctx.info().name +
                     "\" has no VK_KHR_ray_query; use backend=pipeline or backend=auto");
  if (settings.backend == ShadowBackend::Pipeline && !ctx.info().rayTracingPipeline)
    throw InputError("backend=pipeline: device \"" + ctx.info().name +
                     "\" has no VK_KHR_ray_tracing_pipeline; use backend=rayquery or backend=auto");
  sets_.writeBuffer(0, HB_SURFACE_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, in.frameConstants->handle());
  sets_.writeBuffer(0, HB_SHADOW_LIGHTS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, in.lights->handle());
  sets_.writeBuffer(0, HB_SHADOW_GRID, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, in.grid->handle());
  sets_.writeBuffer(0, HB_SHADOW_INDICES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, in.indices->handle());
  sets_.writeImage(0, HB_SURFACE_DEPTH, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, in.depth->view(),
                   VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL, in.sampler);
  if (settings.backend == ShadowBackend::Compute) {
    if (!ctx.info().shaderFloat64)
      throw DeviceError("backend=compute: device \"" + ctx.info().name +
                        "\" lacks shaderFloat64, which its watertight triangle test needs at exact zeros; use "
                        "backend=auto");
    HB_ASSERT(in.bvhNodes && in.bvhTriangles);
    sets_.writeBuffer(0, HB_SURFACE_BVH_NODES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, in.bvhNodes->handle());
    sets_.writeBuffer(0, HB_SURFACE_BVH_TRIANGLES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, in.bvhTriangles->handle());
  } else {
    sets_.writeAccelerationStructure(0, HB_SURFACE_TLAS, in.tlas);
  }
  const bool needsHits = settings.worldPos == WorldPosMethod::Hit || settings.normals == NormalCulling::Geometric;
  if (needsHits && !(in.hitIds && in.hitRays && in.hitTriangles))
    throw InputError(
        "world_pos=hit and normal_culling=geometric need the triangle ids of a computed primary "
        "visibility: set primary=3dr, 3dr-binned, 2dr or raycast");
  // Without them the HB_SURFACE_HIT_* bindings are never read; any buffer of the right type will do.
  sets_.writeBuffer(0, HB_SURFACE_HIT_IDS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                    (in.hitIds ? in.hitIds : in.lights)->handle());
  sets_.writeBuffer(0, HB_SURFACE_HIT_RAYS, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER,
                    (in.hitRays ? in.hitRays : in.frameConstants)->handle());
  sets_.writeBuffer(0, HB_SURFACE_HIT_TRIANGLES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                    (in.hitTriangles ? in.hitTriangles : in.lights)->handle());
  sets_.writeBuffer(0, HB_SHADOW_VISIBILITY, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, visibility_.handle());
  sets_.writeBuffer(0, HB_SHADOW_TRACED, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, traced_.handle());
  const Image* images[3] = {&accounting_, &normals_, &positions_};
  const uint32_t imageBindings[3] = {HB_SHADOW_ACCOUNTING, HB_SHADOW_NORMALS, HB_SHADOW_POSITIONS};
  for (uint32_t i = 0; i < 3; ++i)
    sets_.writeImage(0, imageBindings[i], VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, images[i]->view(), VK_IMAGE_LAYOUT_GENERAL);
  timed_ = std::make_unique<Variant>(ctx, settings, sets_.layout(), false);
  analysis_ = std::make_unique<Variant>(ctx, settings, sets_.layout(), true);
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
  VkDescriptorSet set = sets_.set();
  vkCmdBindPipeline(cmd, v.pipeline().bindPoint(), v.pipeline().handle());
  vkCmdBindDescriptorSets(cmd, v.pipeline().bindPoint(), v.pipeline().layout(), 0, 1, &set, 0, nullptr);
  if (settings_.backend != ShadowBackend::Pipeline) {
    const uint32_t t = settings_.tileSize;
    vkCmdDispatch(cmd, (width_ + t - 1) / t, (height_ + t - 1) / t, 1);
  } else {
    v.rtProgram->traceRays(cmd, width_, height_);
  }
}

}  // namespace hb
