#include "frame/renderer.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include <glm/gtc/packing.hpp>

#include "base/errors.h"
#include "frame/base_parts.h"
#include "frame/frame_builder.h"
#include "frame/passes/depth_prepass.h"
#include "gpu/gpu_lights.h"

namespace hb {

template <typename T>
static std::vector<T> bytesAs(const std::vector<uint8_t>& bytes) {
  std::vector<T> out(bytes.size() / sizeof(T));
  std::memcpy(out.data(), bytes.data(), out.size() * sizeof(T));
  return out;
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
    const bool hardware = settings.primary == PrimaryMethod::Hardware;
    const std::string primary = toString(settings.primary);
    const bool perspectiveOnly = settings.primary == PrimaryMethod::Raster2d ||
                                 settings.primary == PrimaryMethod::Raster2dBinned || primaryUsesBvh(settings.primary);
    if (perspectiveOnly || (hardware && !planar))
      throw InputError(what + " needs primary=3dr, 3dr-binned or raycast" +
                       (planar ? "" : " (or hardware for orthographic)") + " (primary=" + primary + " draws " +
                       (hardware ? "planar views only" : "perspective views only") + ")");
    // The forward pass draws through the view's matrix, which a curved view has not; on top of a
    // compute method its depth test is derived for perspective depth (shading.cpp).
    if (settings.shading != ShadingMethod::Visbuffer && !(planar && hardware))
      throw InputError(what + " needs shading=visbuffer" +
                       (planar ? " with primary=" + primary +
                                     " (the forward pass draws orthographic views only "
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

// What a pass declares it does to the frame's buffers and images (FramePass::stages, access): a
// shader read of what it reads, a shader read and write of what it writes, an image in the layout
// it is published in, unless the pass names the access or declares it inside.
static std::vector<Use> declaredUses(const FramePass& pass, const FrameResources& resources) {
  std::vector<Use> uses;
  auto add = [&](const std::string& name, bool write) {
    if (std::find(pass.syncedInside.begin(), pass.syncedInside.end(), name) != pass.syncedInside.end()) return;
    const Buffer* buffer = resources.buffer(name);
    const Image* image = resources.image(name);
    if (!buffer && !image) return;  // an acceleration structure or a sampler: nothing the frame writes
    Access a{pass.stages, write ? access::kShaderReadWrite : VkAccessFlags2(VK_ACCESS_2_SHADER_READ_BIT),
             image ? resources.imageLayout(name) : VK_IMAGE_LAYOUT_UNDEFINED};
    if (auto named = pass.access.find(name); named != pass.access.end()) a = named->second;
    HB_ASSERT(a.writes() == write);  // a declared access reads what the pass reads, writes what it writes
    uses.push_back(buffer ? Use{*buffer, a} : Use{*image, a});
  };
  for (const std::string& name : pass.reads)
    if (std::find(pass.writes.begin(), pass.writes.end(), name) == pass.writes.end()) add(name, false);
  for (const std::string& name : pass.writes) add(name, true);
  for (const auto& [name, a] : pass.access)  // an access names a resource the pass reads or writes
    HB_ASSERT(std::find(pass.reads.begin(), pass.reads.end(), name) != pass.reads.end() ||
              std::find(pass.writes.begin(), pass.writes.end(), name) != pass.writes.end());
  return uses;
}

// The frame's depth: a D32 image where a pass draws against it (the hardware prepass writes it,
// forward shading tests it), else the colour R32F image the compute primary's resolve writes
// directly (depth_prepass.h kComputeDepthFormat), which saves the copy of a buffer into a D32 image.
static bool drawsAgainstDepth(const RenderSettings& s) {
  return s.primary == PrimaryMethod::Hardware || s.shading != ShadingMethod::Visbuffer;
}

static Image frameDepth(const VulkanContext& ctx, const RenderSettings& s) {
  if (drawsAgainstDepth(s))
    return Image(ctx, s.width, s.height, kDepthFormat,
                 VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                     VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                 VK_IMAGE_ASPECT_DEPTH_BIT);
  return Image(ctx, s.width, s.height, kComputeDepthFormat,
               VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
               VK_IMAGE_ASPECT_COLOR_BIT);
}

Renderer::Renderer(const VulkanContext& ctx, const Scene& scene, const RenderSettings& settings)
    : ctx_(ctx),
      scene_(scene),
      settings_(settings),
      plan_(planFrame(scene, settings.effects, primaryPassOf(settings.primary))),
      camera_(pickCamera(scene, settings)),
      view_(camera_.view),
      proj_(camera_.projection == CameraProjection::Orthographic
                ? reverseZOrthographic(camera_.xmag, camera_.ymag, camera_.znear, camera_.zfar)
                : reverseZProjection(float(settings.width) / float(settings.height), camera_.yfov, camera_.znear,
                                     camera_.zfar)),
      gpuScene_(ctx, scene),
      depth_(frameDepth(ctx, settings)),
      frameConstants_(ctx, sizeof(gpu::FrameConstants), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, true, MemClass::Other),
      lights_(ctx, std::max<size_t>(1, scene.lights.size()) * sizeof(gpu::GpuLight), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
              true, MemClass::Other) {
  // Settings the frame cannot run with are refused before anything is created by hand.
  if (plan_.needs(FrameResource::AccelerationStructures) && !ctx.canTrace())
    throw InputError(
        "device \"" + ctx.info().name +
        "\" cannot trace rays (no ray query, no ray-tracing pipeline); it is usable for raster-only work: " +
        (plan_.runs("shadows") ? "set effects.shadows=false (--set shadows=false)"
                               : "set primary=hardware, 3dr, 3dr-binned or 2dr"));
  VkSamplerCreateInfo si{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  si.magFilter = si.minFilter = VK_FILTER_NEAREST;
  si.addressModeU = si.addressModeV = si.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  VK_CHECK(vkCreateSampler(ctx.device(), &si, nullptr, &pointSampler_));
  // A part below may still refuse (InputError, DeviceError): the destructor does not run then, so
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
  gpu::FrameConstants fc =
      makeFrameConstants(view_, proj_, settings.width, settings.height, settings.tileSize, lightCount,
                         settings.tMin == ShadowTMin::Scaled ? gpu::kShadowTMinPerMetre : 0.0f);
  std::vector<gpu::GpuLight> packed = packLights(scene.lights);
  if (!packed.empty()) std::memcpy(lights_.mapped(), packed.data(), packed.size() * sizeof(gpu::GpuLight));

  // The frame's shared resources, then its parts in frame order: each part finds what the parts
  // before it published (frame/frame_builder.h).
  passesSkipped_ = plan_.skipped;
  if (plan_.needs(FrameResource::AccelerationStructures)) {
    accel_ = &resources_.build<AccelerationStructures>(
        res::kTlas, accelerationStructuresKey(), "renderer",
        [&] { return std::make_unique<AccelerationStructures>(ctx, gpuScene_); },
        [](const AccelerationStructures& as) { return as.bytes(); });
    tracer_.choice = chooseBackend(settings.backend, ctx.info(), settings.rayRates);
    tracer_.tlas = accel_->tlas();
    settings_.backend = tracer_.choice.ran;
    if (tracer_.compute())  // once, for every ray pass
      tracer_.bvh = &frameTraceBvh(resources_, ctx, scene, settings.bvhWidth, "renderer");
  }
  resources_.publish(res::kSceneVertices, gpuScene_.vertices(), "gpu_scene.h vertex", "the scene's vertices");
  resources_.publish(res::kSceneIndices, gpuScene_.indices(), "u32 index", "the scene's triangles x 3");
  resources_.publish(res::kFrameConstants, frameConstants_, "gpu::FrameConstants", "1");
  resources_.publish(res::kLights, lights_, "gpu::GpuLight", std::to_string(lightCount) + " lights");
  resources_.publish(res::kDepth, depth_,
                     drawsAgainstDepth(settings_) ? "reverse-Z D32_SFLOAT"
                                                  : "reverse-Z R32_SFLOAT (a colour image: no pass draws against it)",
                     depthReadLayout(depth_));
  resources_.publishSampler(res::kPointSampler, pointSampler_);
  if (accel_) resources_.publishTlas(res::kTlas, accel_->tlas(), accel_->bytes());
  if (tracer_.bvh)
    resources_.publish(res::kTraceBvh, tracer_.bvh->nodes, "gpu::PrimaryBvhNode (+ triangles, trace_bvh.h)",
                       std::to_string(tracer_.bvh->nodeCount) + " nodes");

  FrameBuilder builder{ctx,   scene,     settings_,  plan_, camera_, view_,
                       proj_, gpuScene_, resources_, fc,    nullptr, rayTracer()};
  auto addPart = [&](std::string name, std::unique_ptr<FramePart> part) {
    for (const FramePass& pass : part->passes()) uses_[&pass] = declaredUses(pass, resources_);
    parts_.emplace_back(std::move(name), std::move(part));
  };
  addPart("primary", std::make_unique<PrimaryPart>(builder));
  if (plan_.needs(FrameResource::LightLists)) addPart("light_lists", std::make_unique<LightListsPart>(builder));
  auto addEffects = [&](FramePhase phase) {
    for (const EffectDef* def : allEffects()) {
      if (def->phase != phase || !plan_.runs(def->name)) continue;
      HB_ASSERT(def->build != nullptr);  // an effect that runs has passes to build
      for (const EffectState& e : plan_.effects)
        if (e.name == def->name) builder.value = e.value;
      addPart(def->name, def->build(builder));
      builder.value = nullptr;
    }
  };
  addEffects(FramePhase::BeforeShading);
  addPart("shading", std::make_unique<ShadingPart>(builder));
  addEffects(FramePhase::AfterShading);
  std::memcpy(frameConstants_.mapped(), &fc, sizeof fc);
  // A pass whose work an earlier part's pass does (an LDM set of the same key) is skipped.
  for (const auto& [partName, part] : parts_)
    for (const auto& [pass, why] : part->skipped()) {
      const auto at = std::find(plan_.passes.begin(), plan_.passes.end(), pass);
      HB_ASSERT(at != plan_.passes.end());  // a part skips a pass the plan does not run
      plan_.passes.erase(at);
      plan_.skipped.push_back({pass, why});
      passesSkipped_.push_back({pass, why});
    }

  // The declarations hold the frame together: every pass the plan runs is built exactly once,
  // and reads only what the frame or a pass before it wrote.
  std::vector<std::string> written;
  for (const char* name : {res::kSceneVertices, res::kSceneIndices, res::kFrameConstants, res::kLights,
                           res::kPointSampler, res::kTlas, res::kTraceBvh})
    if (resources_.has(name)) written.push_back(name);
  uint32_t timerEntries = 0;
  for (const std::string& name : plan_.passes) {
    const FramePass* found = nullptr;
    for (const auto& [partName, part] : parts_)
      for (const FramePass& pass : part->passes())
        if (pass.name == name) {
          HB_ASSERT(found == nullptr);  // two parts build the same pass
          found = &pass;
        }
    HB_ASSERT(found != nullptr && found->record);  // the plan runs a pass no part built
    for (const std::string& read : found->reads) {
      resources_.use(read, name);
      const bool before = std::find(written.begin(), written.end(), read) != written.end();
      if (!before)
        std::fprintf(stderr, "internal error: pass %s reads %s before any pass writes it\n", name.c_str(),
                     read.c_str());
      HB_ASSERT(before);
    }
    written.insert(written.end(), found->writes.begin(), found->writes.end());
    order_.push_back(found);
    timerEntries += 1 + uint32_t(found->subPasses.size());
  }
  size_t built = 0;
  for (const auto& [partName, part] : parts_) built += part->passes().size();
  HB_ASSERT(built == order_.size());  // a part built a pass the plan does not run
  timer_ = std::make_unique<GpuTimer>(ctx, std::max(timerEntries, 1u));
  samplerGuard.armed = false;  // ~Renderer destroys it from here on
}

Renderer::~Renderer() {
  vkDeviceWaitIdle(ctx_.device());
  parts_.clear();  // before the sampler they sample with
  vkDestroySampler(ctx_.device(), pointSampler_, nullptr);
}

std::vector<const FramePass*> Renderer::framePasses() const { return order_; }

bool Renderer::hasCulling() const { return part<LightListsPart>("light_lists") != nullptr; }

uint64_t Renderer::listMemoryBytes() const {
  const LightListsPart* lists = part<LightListsPart>("light_lists");
  return lists ? lists->culling().memoryBytes() : 0;
}

const Raster3dPass* Renderer::raster3d() const { return part<PrimaryPart>("primary")->raster3d(); }

FrameTiming Renderer::renderFrame(bool analysis) {
  // A part that adapted to what the frame found (a work list grown to the frame's demand) has the
  // frame rendered again, so that its work and counts are those of every later frame. One growth
  // fits the same view; the bound only guards against a part that never settles.
  for (int attempt = 0;; ++attempt) {
    FrameTiming t = renderFrameOnce(analysis);
    bool again = false;
    for (const auto& [name, part] : parts_) again = part->afterFrame() || again;
    if (!again) return t;
    HB_ASSERT(attempt < 3);
  }
}

FrameTiming Renderer::renderFrameOnce(bool analysis) {
  passesRun_.clear();
  ctx_.submitAndWait([&](VkCommandBuffer cmd) {
    GpuTimer& timer = *timer_;
    Sync sync;  // every barrier of the frame, from the passes' declared accesses
    timer.reset(cmd);
    if (!onceDone_)  // once per camera/resolution/tile size
      for (const auto& [name, part] : parts_) part->recordOnce(cmd, sync);
    onceDone_ = true;
    timer.frameBegin(cmd);
    const PassFrame frame{analysis, &timer, &sync};
    for (const FramePass* pass : order_) {
      sync.use(cmd, uses_.at(pass));  // outside the pass's timed interval
      timer.begin(cmd, pass->name);
      pass->record(cmd, frame);
      timer.end(cmd);
      passesRun_.push_back(pass->name);
    }
    timer.frameEnd(cmd);
  });
  FrameTiming t;
  t.passMs = timer_->read(&t.frameMs);
  return t;
}

std::vector<float> Renderer::readDepth() const {
  std::vector<uint8_t> bytes = readbackImage(ctx_, depth_, depthReadLayout(depth_), 4);
  std::vector<float> out(bytes.size() / 4);
  std::memcpy(out.data(), bytes.data(), bytes.size());
  return out;
}

CullingReadback Renderer::readCulling() const {
  const LightListsPart* lists = part<LightListsPart>("light_lists");
  HB_ASSERT(lists);
  const LightCulling& culling = lists->culling();
  CullingOutputs o = culling.outputs();
  CullingReadback r;
  r.lists = culling.settings().lists;
  r.tilesX = o.tilesX;
  r.tilesY = o.tilesY;
  const size_t tiles = size_t(o.tilesX) * o.tilesY;
  const std::vector<uint32_t> grid = bytesAs<uint32_t>(readbackBuffer(ctx_, *o.grid));
  const std::vector<uint32_t> words = bytesAs<uint32_t>(readbackBuffer(ctx_, *o.indices));
  HB_ASSERT(grid.size() >= tiles * 4);
  if (r.lists == LightLists::Tile) {
    r.capacity = culling.settings().capacity;
    for (size_t t = 0; t < tiles; ++t) {
      r.offset.push_back(grid[4 * t]);
      r.count.push_back(grid[4 * t + 1]);
      r.total.push_back(grid[4 * t + 2]);
    }
    r.indices = words;
    return r;
  }
  // Masks: every set bit, ascending, as a scene light index (zbin: through the sort's order).
  const uint32_t lightCount = uint32_t(scene_.lights.size()), maskWords = culling.maskWords();
  r.capacity = lightCount;
  if (r.lists == LightLists::Zbin) {
    r.order = bytesAs<uint32_t>(readbackBuffer(ctx_, culling.order()));
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

gpu::FrameConstants Renderer::frameConstants() const {
  gpu::FrameConstants fc;
  std::memcpy(&fc, frameConstants_.mapped(), sizeof fc);
  return fc;
}

std::vector<float> Renderer::readColor() const {
  return readbackHalfImage(ctx_, resources_.requireImage(res::kColor), resources_.imageLayout(res::kColor));
}

std::vector<float> Renderer::readRefNormals() const {
  std::vector<uint8_t> bytes =
      readbackImage(ctx_, resources_.requireImage(res::kRefNormals), resources_.imageLayout(res::kRefNormals), 16);
  std::vector<float> out(bytes.size() / 4);
  std::memcpy(out.data(), bytes.data(), bytes.size());
  return out;
}

}  // namespace hb
