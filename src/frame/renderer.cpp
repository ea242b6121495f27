#include "frame/renderer.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include <glm/gtc/packing.hpp>

#include "base/errors.h"
#include "effects/ambient_occlusion.h"
#include "effects/indirect.h"
#include "gpu/gpu_lights.h"

namespace hb {

template <typename T>
static std::vector<T> bytesAs(const std::vector<uint8_t>& bytes) {
  std::vector<T> out(bytes.size() / sizeof(T));
  std::memcpy(out.data(), bytes.data(), out.size() * sizeof(T));
  return out;
}

static std::string primaryPassName(const std::string& primary) {
  if (primary == "hardware") return "depth_prepass";
  return primaryModeFrom(primary) == PrimaryMode::RayCast ? "raycast" : "raster3d";
}

// The camera, with the projection the settings ask for. A perspective camera made orthographic
// keeps its extent at the scene's centre: ymag = tan(yfov/2)·(view depth of the bounds' centre),
// xmag = ymag·W/H. Views a method cannot render are refused here, with what to set instead.
static Camera pickCamera(const Scene& scene, const RenderSettings& settings) {
  const uint32_t index = settings.cameraIndex;
  if (scene.cameras.empty())
    throw InputError("scene \"" + scene.name + "\" has no camera; add one to the glTF or set a camera in the config");
  if (index >= scene.cameras.size())
    throw InputError("camera index " + std::to_string(index) + " does not exist; the scene has " +
                     std::to_string(scene.cameras.size()));
  Camera c = scene.cameras[index];
  if (settings.projection && *settings.projection != c.projection) {
    if (*settings.projection == CameraProjection::Orthographic && c.projection == CameraProjection::Perspective) {
      glm::vec3 lo, hi;
      scene.bounds(lo, hi);
      const glm::vec3 centre = glm::vec3(c.view * glm::vec4(0.5f * (lo + hi), 1.0f));
      const float depth = std::max(-centre.z, c.znear);
      c.ymag = std::tan(0.5f * c.yfov) * depth;
      c.xmag = c.ymag * float(settings.width) / float(settings.height);
    }
    c.projection = *settings.projection;
  }
  if (c.projection != CameraProjection::Perspective) {
    const std::string what = std::string("projection=") + toString(c.projection);
    const bool planar = c.projection == CameraProjection::Orthographic;
    if (settings.primary == "2dr" || (settings.primary == "hardware" && !planar))
      throw InputError(what + " needs primary=3dr, 3dr-binned or raycast" + (planar ? "" : " (or hardware for orthographic)") +
                       " (primary=" + settings.primary + " draws " +
                       (settings.primary == "hardware" ? "planar views only" : "perspective views only") + ")");
    // The forward pass draws through the view's matrix, which a curved view has not; on top of a
    // compute method its depth test is derived for perspective depth (shading.cpp).
    if (!settings.visbufferShading && !(planar && settings.primary == "hardware"))
      throw InputError(what + " needs shading=visbuffer" +
                       (planar ? " with primary=" + settings.primary + " (the forward pass draws orthographic views only "
                                                                     "on top of primary=hardware)"
                               : " (the forward pass rasterizes through a planar matrix)"));
    if (settings.lightCulling)
      throw InputError(what + " needs light_culling=false (the light tiles are frusta of a perspective view)");
  }
  // The depth image holds reverse-Z D/t − C, 0 for "nothing": znear must be positive (a glTF
  // orthographic camera may say 0). A millionth of zfar cuts only what touches the view plane.
  if (!(c.znear > 0.0f)) c.znear = c.zfar * 1e-6f;
  return c;
}

Renderer::Renderer(const VulkanContext& ctx, const Scene& scene, const RenderSettings& settings)
    : ctx_(ctx),
      scene_(scene),
      settings_(settings),
      plan_(planFrame(scene, settings.effects, primaryPassName(settings.primary))),
      camera_(pickCamera(scene, settings)),
      view_(camera_.view),
      proj_(camera_.projection == CameraProjection::Orthographic
                ? reverseZOrthographic(camera_.xmag, camera_.ymag, camera_.znear, camera_.zfar)
                : reverseZProjection(float(settings.width) / float(settings.height), camera_.yfov, camera_.znear,
                                     camera_.zfar)),
      gpuScene_(ctx, scene),
      depth_(ctx, settings.width, settings.height, kDepthFormat,
             VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                 VK_IMAGE_USAGE_TRANSFER_DST_BIT,
             VK_IMAGE_ASPECT_DEPTH_BIT),
      frameConstants_(ctx, sizeof(gpu::FrameConstants), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, true, MemClass::Other),
      lights_(ctx, std::max<size_t>(1, scene.lights.size()) * sizeof(gpu::GpuLight), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
              true, MemClass::Other),
      depthPrepass_(ctx),
      timer_(ctx, 24) {
  // Settings the frame cannot run with are refused before anything is created by hand.
  // Depth turns back into positions through a planar matrix (perspective or orthographic).
  const bool curved = camera_.projection != CameraProjection::Perspective &&
                      camera_.projection != CameraProjection::Orthographic;
  if (curved && plan_.hasPass("shadows") && settings.worldPos != gpu::kWorldPosHit)
    throw InputError(std::string("projection=") + toString(camera_.projection) +
                     " with shadows needs world_pos=hit (depth is turned back into positions through a planar "
                     "matrix otherwise)");
  if (plan_.needs(FrameResource::AccelerationStructures) && !ctx.canTrace())
    throw InputError("device \"" + ctx.info().name +
                     "\" cannot trace rays (no ray query, no ray-tracing pipeline); it is usable for raster-only work: " +
                     (plan_.hasPass("shadows") ? "set effects.shadows=false (--set shadows=false)"
                                               : "set primary=hardware, 3dr, 3dr-binned or 2dr"));
  VkSamplerCreateInfo si{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  si.magFilter = si.minFilter = VK_FILTER_NEAREST;
  si.addressModeU = si.addressModeV = si.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  VK_CHECK(vkCreateSampler(ctx.device(), &si, nullptr, &pointSampler_));
  // A pass below may still refuse (InputError, DeviceError): the destructor does not run then, so
  // the sampler is destroyed here unless the constructor completes.
  struct SamplerGuard {
    VkDevice device;
    VkSampler sampler;
    bool armed = true;
    ~SamplerGuard() {
      if (armed) vkDestroySampler(device, sampler, nullptr);
    }
  } samplerGuard{ctx.device(), pointSampler_};

  const uint32_t lightCount = uint32_t(scene.lights.size());
  gpu::FrameConstants fc = makeFrameConstants(view_, proj_, settings.width, settings.height, settings.tileSize, lightCount,
                                              settings.scaledTMin ? gpu::kShadowTMinPerMetre : 0.0f);
  if (plan_.runs("ambient_occlusion")) {  // the ambient term lights the frame through AO only (scene.h)
    HB_ASSERT(scene.ambient);
    fc.ambient = glm::vec4(scene.ambient->color * scene.ambient->intensity, 1.0f);
  }
  std::memcpy(frameConstants_.mapped(), &fc, sizeof fc);
  std::vector<gpu::GpuLight> packed = packLights(scene.lights);
  if (!packed.empty()) std::memcpy(lights_.mapped(), packed.data(), packed.size() * sizeof(gpu::GpuLight));

  // The frame follows the plan (effects/effects.h): light lists when direct light or an effect
  // needs them, acceleration structures and the shadow pass only when the shadows effect runs.
  passesSkipped_ = plan_.skipped;
  if (plan_.needs(FrameResource::AccelerationStructures)) accel_ = std::make_unique<AccelerationStructures>(ctx, gpuScene_);
  if (plan_.hasPass("raster3d") || plan_.hasPass("raycast")) {
    RayCastInputs cast;
    if (accel_) cast = {accel_->tlas(), ctx.info().rayQuery};
    raster3d_ = std::make_unique<Raster3dPass>(ctx, scene, camera_, settings.width, settings.height,
                                               primaryModeFrom(settings.primary), settings.r3dThreadBox,
                                               settings.fp64Fallback, cast);
  }
  if (plan_.needs(FrameResource::LightLists)) {
    CullingSettings cs;
    cs.tileSize = settings.tileSize;
    cs.lightCulling = settings.lightCulling;
    cs.aabb = settings.aabb;
    cs.depthSlices = settings.depthSlices;
    cs.lists = settings.lightLists;
    cs.lightCount = lightCount;
    if (settings.lightLists == LightLists::Zbin) {
      // The bins span the near plane to the farthest corner of the scene's bounds in view depth.
      glm::vec3 lo, hi;
      scene.bounds(lo, hi);
      float far = 0.0f;
      for (int c = 0; c < 8; ++c) {
        const glm::vec3 corner(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z);
        far = std::max(far, -(view_ * glm::vec4(corner, 1.0f)).z);
      }
      cs.zbinNear = camera_.znear;
      cs.zbinFar = std::max(far, 2.0f * camera_.znear);
    }
    culling_ = std::make_unique<LightCulling>(ctx, cs, settings.width, settings.height, frameConstants_, lights_,
                                              depth_, pointSampler_);
    fc.lists = culling_->listConstants();
    fc.zbins = culling_->zbinConstants();
    std::memcpy(frameConstants_.mapped(), &fc, sizeof fc);
  }
  if (plan_.hasPass("shadows")) {
    HB_ASSERT(culling_ && accel_);
    ShadowSettings ss;
    if (settings.backend == "auto")
      ss.backend = ctx.info().rayQuery ? ShadowBackend::RayQuery : ShadowBackend::Pipeline;
    else if (settings.backend == "rayquery")
      ss.backend = ShadowBackend::RayQuery;
    else if (settings.backend == "pipeline")
      ss.backend = ShadowBackend::Pipeline;
    else
      throw InputError("backend \"" + settings.backend + "\" is not one of auto, rayquery, pipeline");
    ss.tileSize = settings.tileSize;
    ss.normals = settings.normals;
    ss.worldPos = settings.worldPos;
    ss.rangeTest = settings.rangeTest;
    ss.listMode = fc.lists.x;
    ss.visibilityWords = fc.lists.z;
    CullingOutputs co = culling_->outputs();
    shadowInputs_ = {&frameConstants_, co.lights, co.grid, co.indices, &depth_, pointSampler_, accel_->tlas()};
    if (raster3d_) {
      shadowInputs_.hitIds = &raster3d_->visibility();
      shadowInputs_.hitRays = &raster3d_->constants();
      shadowInputs_.hitTriangles = &raster3d_->triangles();
    }
    shadows_ = std::make_unique<ShadowPass>(ctx, ss, settings.width, settings.height, shadowInputs_);
  }
  if (plan_.hasPass("ambient_occlusion")) {
    AoPassSettings as;
    for (const EffectState& e : plan_.effects)
      if (e.name == "ambient_occlusion") as.ao = aoSettingsOf(e.value);
    // The shadow pass's positions; a normal always (AO has no "off"): the triangle's own where the
    // primary gives ids, else the improved reconstruction.
    as.worldPos = settings.worldPos;
    as.normals = raster3d_ ? gpu::kNormalsGeometric : gpu::kNormalsImproved;
    AoInputs ai{&frameConstants_, &depth_, pointSampler_, accel_ ? accel_->tlas() : VK_NULL_HANDLE};
    if (raster3d_) {
      ai.hitIds = &raster3d_->visibility();
      ai.hitRays = &raster3d_->constants();
      ai.hitTriangles = &raster3d_->triangles();
    } else if (settings.worldPos == gpu::kWorldPosHit) {
      throw InputError("world_pos=hit needs the triangle ids of a computed primary visibility: set primary=3dr, "
                       "3dr-binned, 2dr or raycast");
    }
    ao_ = std::make_unique<AoPass>(ctx, gpuScene_, scene, as, settings.width, settings.height, ai);
  }
  if (plan_.runs("indirect")) {
    IndirectPassSettings is;
    for (const EffectState& e : plan_.effects)
      if (e.name == "indirect") is.indirect = indirectSettingsOf(e.value);
    is.worldPos = settings.worldPos;  // the surface as ambient occlusion takes it
    is.normals = raster3d_ ? gpu::kNormalsGeometric : gpu::kNormalsImproved;
    is.rayQuery = settings.backend != "pipeline" && ctx.info().rayQuery;  // backend=pipeline: every ray pass
    HB_ASSERT(accel_);
    IndirectInputs ii{&frameConstants_, &lights_, &depth_, pointSampler_, accel_->tlas()};
    if (raster3d_) {
      ii.hitIds = &raster3d_->visibility();
      ii.hitRays = &raster3d_->constants();
      ii.hitTriangles = &raster3d_->triangles();
    } else if (settings.worldPos == gpu::kWorldPosHit) {
      throw InputError("world_pos=hit needs the triangle ids of a computed primary visibility: set primary=3dr, "
                       "3dr-binned, 2dr or raycast");
    }
    indirect_ = std::make_unique<IndirectPass>(ctx, gpuScene_, scene, is, settings.width, settings.height, ii);
  }
  CullingOutputs cullOut = culling_ ? culling_->outputs() : CullingOutputs{};
  ShadingInputs shadingIn{&frameConstants_, cullOut.lights ? cullOut.lights : &lights_, cullOut.grid,
                          cullOut.indices, shadows_ ? &shadows_->visibility() : nullptr, &depth_, settings.tileSize,
                          culling_ ? fc.lists.x : gpu::kListTile, raster3d_ ? &raster3d_->visibility() : nullptr,
                          settings.r3dShadingDepthTest, settings.visbufferShading,
                          raster3d_ ? &raster3d_->constants() : nullptr, ao_ ? &ao_->output() : nullptr,
                          indirect_ ? &indirect_->irradiance() : nullptr};
  shading_ = std::make_unique<ShadingPass>(ctx, gpuScene_, settings.width, settings.height, shadingIn);
  samplerGuard.armed = false;  // ~Renderer destroys it from here on
}

Renderer::~Renderer() {
  vkDeviceWaitIdle(ctx_.device());
  vkDestroySampler(ctx_.device(), pointSampler_, nullptr);
}

FrameTiming Renderer::renderFrame(bool analysis) {
  passesRun_.clear();
  const uint32_t lightCount = uint32_t(scene_.lights.size());
  ctx_.submitAndWait([&](VkCommandBuffer cmd) {
    timer_.reset(cmd);
    if (culling_ && !frustumsDone_) culling_->recordFrustums(cmd);  // once per camera/resolution/tile size
    frustumsDone_ = true;
    timer_.frameBegin(cmd);

    if (raster3d_) {
      const char* pass = raster3d_->mode() == PrimaryMode::RayCast ? "raycast" : "raster3d";
      timer_.begin(cmd, pass);
      raster3d_->record(cmd, depth_, analysis, &timer_);  // leaves depth_ in DEPTH_READ_ONLY_OPTIMAL
      timer_.end(cmd);
      passesRun_.push_back(pass);
    } else {
      imageBarrier(cmd, depth_, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                   VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT,
                   VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                   VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT);
      timer_.begin(cmd, "depth_prepass");
      depthPrepass_.record(cmd, gpuScene_, proj_ * view_, depth_);
      timer_.end(cmd);
      passesRun_.push_back("depth_prepass");
      imageBarrier(cmd, depth_, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL,
                   VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT, VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR |
                       VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_COPY_BIT,
                   VK_ACCESS_2_SHADER_SAMPLED_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                       VK_ACCESS_2_TRANSFER_READ_BIT);
    }

    if (culling_) {
      timer_.begin(cmd, "light_culling");
      culling_->recordCulling(cmd, lightCount);
      timer_.end(cmd);
      passesRun_.push_back("light_culling");
      memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR |
                        VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COPY_BIT,
                    VK_ACCESS_2_SHADER_READ_BIT | VK_ACCESS_2_TRANSFER_READ_BIT);
    }
    if (shadows_) {
      timer_.begin(cmd, "shadows");
      shadows_->record(cmd, analysis);
      timer_.end(cmd);
      passesRun_.push_back("shadows");
      memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR,
                    VK_ACCESS_2_SHADER_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COPY_BIT |
                        VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR,
                    VK_ACCESS_2_SHADER_READ_BIT | VK_ACCESS_2_SHADER_WRITE_BIT | VK_ACCESS_2_TRANSFER_READ_BIT);
    }
    if (ao_) {
      if (ao_->buildsLdms()) {
        timer_.begin(cmd, "ldm_build");
        ao_->recordBuild(cmd);
        timer_.end(cmd);
        passesRun_.push_back("ldm_build");
      }
      timer_.begin(cmd, "ambient_occlusion");
      ao_->recordAo(cmd);
      timer_.end(cmd);
      passesRun_.push_back("ambient_occlusion");
    }
    if (indirect_) {
      auto pass = [&](const char* name, auto&& record) {
        timer_.begin(cmd, name);
        record();
        timer_.end(cmd);
        passesRun_.push_back(name);
      };
      if (indirect_->buildsLdms()) pass("indirect_ldm_build", [&] { indirect_->recordBuild(cmd); });
      if (indirect_->method() == IndirectMethod::Reference) {
        pass("indirect_gather", [&] { indirect_->recordGather(cmd); });
      } else {
        pass("photon_trace", [&] { indirect_->recordTrace(cmd); });
        pass("photon_splat", [&] { indirect_->recordSplat(cmd); });
      }
    }
    timer_.begin(cmd, "shading");
    shading_->record(cmd, proj_ * view_, analysis);
    timer_.end(cmd);
    passesRun_.push_back("shading");
    memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                  VK_PIPELINE_STAGE_2_COPY_BIT | VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                  VK_ACCESS_2_TRANSFER_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    timer_.frameEnd(cmd);
  });
  FrameTiming t;
  t.passMs = timer_.read(&t.frameMs);
  return t;
}

std::vector<double> Renderer::rayBench(uint32_t repetitions) {
  HB_ASSERT(shadows_);
  if (!rayBench_)
    rayBench_ = std::make_unique<RayBenchPass>(ctx_, shadows_->settings().backend, settings_.width, settings_.height,
                                               shadowInputs_, *shadows_);
  std::vector<double> ms;
  for (uint32_t r = 0; r < repetitions; ++r) {
    ctx_.submitAndWait([&](VkCommandBuffer cmd) {
      timer_.reset(cmd);
      timer_.frameBegin(cmd);
      timer_.begin(cmd, "raybench");
      rayBench_->record(cmd);
      timer_.end(cmd);
      timer_.frameEnd(cmd);
    });
    auto t = timer_.read(nullptr);
    ms.push_back(t.empty() ? 0.0 : t[0].second);
  }
  return ms;
}

std::vector<float> Renderer::readDepth() const {
  std::vector<uint8_t> bytes = readbackImage(ctx_, depth_, VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL, 4);
  std::vector<float> out(bytes.size() / 4);
  std::memcpy(out.data(), bytes.data(), bytes.size());
  return out;
}

CullingReadback Renderer::readCulling() const {
  HB_ASSERT(culling_);
  CullingOutputs o = culling_->outputs();
  CullingReadback r;
  r.lists = culling_->settings().lists;
  r.tilesX = o.tilesX;
  r.tilesY = o.tilesY;
  const size_t tiles = size_t(o.tilesX) * o.tilesY;
  const std::vector<uint32_t> grid = bytesAs<uint32_t>(readbackBuffer(ctx_, *o.grid));
  const std::vector<uint32_t> words = bytesAs<uint32_t>(readbackBuffer(ctx_, *o.indices));
  HB_ASSERT(grid.size() >= tiles * 4);
  if (r.lists == LightLists::Tile) {
    r.capacity = culling_->settings().capacity;
    for (size_t t = 0; t < tiles; ++t) {
      r.offset.push_back(grid[4 * t]);
      r.count.push_back(grid[4 * t + 1]);
      r.total.push_back(grid[4 * t + 2]);
    }
    r.indices = words;
    return r;
  }
  // Masks: every set bit, ascending, as a scene light index (zbin: through the sort's order).
  const uint32_t lightCount = uint32_t(scene_.lights.size()), maskWords = culling_->maskWords();
  r.capacity = lightCount;
  if (r.lists == LightLists::Zbin) {
    r.order = bytesAs<uint32_t>(readbackBuffer(ctx_, culling_->order()));
    r.order.resize(lightCount);
    const size_t binsAt = tiles * maskWords;
    HB_ASSERT(words.size() >= binsAt + gpu::kZBins);
    r.bins.assign(words.begin() + binsAt, words.begin() + binsAt + gpu::kZBins);
  }
  for (size_t t = 0; t < tiles; ++t) {
    HB_ASSERT(grid[4 * t] == t * maskWords);
    r.offset.push_back(uint32_t(r.indices.size()));
    for (uint32_t w = 0; w < maskWords; ++w)
      for (uint32_t bits = words[t * maskWords + w]; bits != 0; bits &= bits - 1) {
        const uint32_t k = w * 32 + uint32_t(std::countr_zero(bits));
        if (r.lists == LightLists::Zbin) {
          r.sorted.push_back(k);
          r.indices.push_back(k < r.order.size() ? r.order[k] : ~0u);
        } else {
          r.indices.push_back(k);
        }
      }
    r.count.push_back(uint32_t(r.indices.size()) - r.offset.back());
    r.total.push_back(grid[4 * t + 2]);
  }
  return r;
}

std::pair<uint32_t, uint32_t> CullingReadback::pixelSlice(uint32_t tile, uint32_t range) const {
  const uint32_t first = offset[tile], last = offset[tile] + count[tile];
  if (lists != LightLists::Zbin) return {first, last};
  // The tile's sorted indices ascend: the range [lo, hi) is one contiguous run of them.
  const uint32_t lo = range & 0xFFFFu, hi = range >> 16;
  const auto b = sorted.begin();
  const uint32_t from = uint32_t(std::lower_bound(b + first, b + last, lo) - b);
  const uint32_t to = uint32_t(std::lower_bound(b + first, b + last, std::max(lo, hi)) - b);
  return {from, to};
}

template <typename T>
static std::vector<T> readImageAs(const VulkanContext& ctx, const Image& img, uint32_t bytesPerPixel) {
  std::vector<uint8_t> bytes = readbackImage(ctx, img, VK_IMAGE_LAYOUT_GENERAL, bytesPerPixel);
  std::vector<T> out(bytes.size() / sizeof(T));
  std::memcpy(out.data(), bytes.data(), bytes.size());
  return out;
}

std::vector<float> Renderer::readColor() const {
  std::vector<uint8_t> bytes = readbackImage(ctx_, shading_->color(), VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, 8);
  std::vector<float> out(bytes.size() / 2);
  for (size_t i = 0; i < out.size(); ++i) {
    uint16_t h;
    std::memcpy(&h, bytes.data() + 2 * i, 2);
    out[i] = glm::unpackHalf1x16(h);
  }
  return out;
}

std::vector<float> Renderer::readRefNormals() const {
  std::vector<uint8_t> bytes =
      readbackImage(ctx_, shading_->refNormals(), VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, 16);
  std::vector<float> out(bytes.size() / 4);
  std::memcpy(out.data(), bytes.data(), bytes.size());
  return out;
}

ShadowReadback Renderer::readShadows() const {
  HB_ASSERT(shadows_);
  ShadowReadback r;
  const size_t pixels = size_t(settings_.width) * settings_.height;
  r.words = shadows_->settings().visibilityWords;
  r.visibility = bytesAs<uint32_t>(readbackBuffer(ctx_, shadows_->visibility()));
  HB_ASSERT(r.visibility.size() >= r.words * pixels);
  if (shadows_->settings().listMode == gpu::kListZbin)
    r.ranges.assign(r.visibility.begin() + r.words * pixels, r.visibility.begin() + (r.words + 1) * pixels);
  r.visibility.resize(r.words * pixels);
  r.accounting = readImageAs<uint32_t>(ctx_, shadows_->accounting(), 16);
  r.normals = readImageAs<float>(ctx_, shadows_->normals(), 16);
  r.positions = readImageAs<float>(ctx_, shadows_->positions(), 16);
  return r;
}

}  // namespace hb
