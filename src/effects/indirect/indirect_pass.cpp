#include "effects/indirect/indirect_pass.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "base/errors.h"
#include "effects/indirect/indirect_splat.h"
#include "frame/passes/depth_prepass.h"
#include "gpu/descriptor_binder.h"
#include "gpu/raster_pipeline.h"
#include "reference/eq_partition.h"
#include "reference/photon_ref.h"
#include "shared/gpu_types.h"

namespace hb {

namespace {

constexpr VkFormat kIrradianceFormat = VK_FORMAT_R32G32B32A32_SFLOAT;

// A spot light whose cone reaches within 3° of its plane (tan → ∞) emits through a cube instead.
constexpr double kSpotCubeCos = 0.05;

double spotFactor(const Light& l, const glm::dvec3& d) {
  if (l.type != LightType::Spot) return 1.0;
  const double cosOuter = std::cos(double(l.outerConeAngle)), cosInner = std::cos(double(l.innerConeAngle));
  const double t =
      std::clamp((glm::dot(glm::dvec3(l.direction), d) - cosOuter) / std::max(cosInner - cosOuter, 1e-4), 0.0, 1.0);
  return t * t;
}

}  // namespace

PhotonTally tallyPhotons(const std::vector<gpu::Photon>& photons) {
  PhotonTally t;
  t.slots = photons.size();
  for (const gpu::Photon& p : photons) {
    uint32_t status;
    std::memcpy(&status, &p.normalStatus.w, 4);
    const double flux = double(p.positionFluxR.w) + double(p.duFluxG.w) + double(p.dvFluxB.w);
    switch (status) {
      case gpu::kPhotonStored:
        ++t.stored;
        t.fluxStored += flux;
        break;
      case gpu::kPhotonHidden:
        ++t.hidden;
        t.fluxHidden += flux;
        break;
      case gpu::kPhotonEscaped:
        ++t.escaped;
        t.fluxEscaped += flux;
        break;
      case gpu::kPhotonGrazing:
        ++t.grazing;
        t.fluxGrazing += flux;
        break;
      default: ++t.empty; break;
    }
  }
  return t;
}

struct IndirectPass::Program {
  Pipeline compute;
  std::unique_ptr<RaygenMissPipeline> rt;
  explicit Program(const VulkanContext& c) : compute(c) {}
  const Pipeline& pipeline() const { return rt ? rt->pipeline() : compute; }
};

IndirectPass::IndirectPass(const VulkanContext& ctx, const GpuScene& gpuScene, const Scene& scene,
                           const IndirectPassSettings& settings, uint32_t width, uint32_t height,
                           const IndirectInputs& in, const LdmSource& ldmSource)
    : ctx_(ctx), gpuScene_(gpuScene), settings_(settings), in_(in), width_(width), height_(height), splat_(ctx) {
  const IndirectSettings& s = settings.indirect;
  if (!in.tlas)
    throw InputError(
        "effects.indirect needs the ray tracer (its photons and gathered rays meet surfaces by ray); "
        "this device has none");
  VkFormatProperties fp{};
  vkGetPhysicalDeviceFormatProperties(ctx.physical(), kIrradianceFormat, &fp);
  const VkFormatFeatureFlags needed =
      VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BLEND_BIT | VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT;
  if ((fp.optimalTilingFeatures & needed) != needed)
    throw DeviceError("device \"" + ctx.info().name +
                      "\" cannot blend into or store RGBA32F images, which photon "
                      "splatting needs; use effects.indirect.method=reference or another device");
  // Beyond the first bounce a photon needs the surface it landed on (its normal and albedo): the
  // ray tracer returns it, and of the LDM lists only sbuffer's hold triangle ids.
  if (s.bounces > 1 && s.method == IndirectMethod::Ldm && s.ldmList != LdmList::Sbuffer)
    throw InputError("effects.indirect.bounces: " + std::to_string(s.bounces) +
                     " bounces with method ldm need ldm_list \"sbuffer\" (its lists hold the triangle ids a photon "
                     "bounces off); set \"ldm_list\": \"sbuffer\" or \"bounces\": 1");
  std::vector<glm::dvec3> dirs;
  try {
    dirs = ldmDirections(s.directions);
  } catch (const std::invalid_argument& e) {
    throw InputError(std::string("effects.indirect.directions: ") + e.what());
  }

  // The emitters' faces, their primaries and the flux leaving through them (in double).
  std::vector<gpu::PhotonFace> faces;
  for (uint32_t li = 0; li < scene.lights.size(); ++li) {
    const Light& l = scene.lights[li];
    if (l.type == LightType::Directional || !(l.intensity > 0.0f)) continue;
    ++emitters_;
    std::vector<PhotonFace> lf;
    if (l.type == LightType::Spot && std::cos(double(l.outerConeAngle)) > kSpotCubeCos)
      lf.push_back(spotFace(glm::normalize(glm::dvec3(l.direction)), std::cos(double(l.outerConeAngle)), s.photons));
    else
      lf = cubeFaces(s.photons);
    const double rgb = double(l.color.r) + double(l.color.g) + double(l.color.b);
    for (const PhotonFace& f : lf) {
      faces.push_back({glm::vec4(glm::vec3(f.forward), float(f.halfExtent)), glm::vec4(glm::vec3(f.right), 0.0f),
                       glm::vec4(glm::vec3(f.up), 0.0f), li, primaries_, 0, 0});
      for (uint32_t b = 0; b < s.photons; ++b)
        for (uint32_t a = 0; a < s.photons; ++a)
          emittedFlux_ += double(l.intensity) * rgb * texelSolidAngle(f, a, b) * spotFactor(l, texelDirection(f, a, b));
      const uint64_t next = uint64_t(primaries_) + uint64_t(s.photons) * s.photons;
      if (next > 0xFFFFFFFFull) throw InputError("effects.indirect.photons: too many primary photons; lower photons");
      primaries_ = uint32_t(next);
    }
  }
  HB_ASSERT(!faces.empty());  // effects/indirect.cpp cannotAct
  VkPhysicalDeviceProperties props;
  vkGetPhysicalDeviceProperties(ctx.physical(), &props);
  const uint64_t photonBytes = slots() * sizeof(gpu::Photon);
  if (photonBytes > props.limits.maxStorageBufferRange || slots() > 0xFFFFFFFFull) {
    std::string shape = std::to_string(primaries_) + " primaries x " + std::to_string(s.directions) + " directions";
    for (uint32_t b = 2; b <= s.bounces; ++b) shape += " x " + std::to_string(s.directionsAtBounce(b));
    throw InputError("effects.indirect: " + std::to_string(slots()) + " photon slots (" + shape + ", " +
                     std::to_string(photonBytes >> 20) + " MiB) exceed this device's storage-buffer range of " +
                     std::to_string(props.limits.maxStorageBufferRange >> 20) + " MiB; lower photons or directions" +
                     (s.bounces > 1 ? ", bounces or bounce_directions" : ""));
  }

  std::vector<glm::vec4> packed;
  for (const glm::dvec3& d : dirs) packed.emplace_back(glm::vec3(d), 0.0f);
  directions_ = uploadBuffer(ctx, packed.data(), packed.size() * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                             MemClass::Other);
  faces_ = uploadBuffer(ctx, faces.data(), faces.size() * sizeof(gpu::PhotonFace), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                        MemClass::Other);
  const DrawTables tables = drawTables(gpuScene);
  draws_ = uploadBuffer(ctx, tables.draws.data(), tables.draws.size() * sizeof(gpu::GpuDraw),
                        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemClass::Geometry);
  triangleDraw_ =
      uploadBuffer(ctx, tables.triangleDraw.data(), std::max<size_t>(1, tables.triangleDraw.size()) * sizeof(uint32_t),
                   VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemClass::Geometry);
  const std::vector<uint32_t> idBase = triangleIdBase(scene);
  idBase_ = uploadBuffer(ctx, idBase.data(), idBase.size() * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                         MemClass::Other);
  placeholder_ = Buffer(ctx, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, MemClass::Other);
  textures_ = std::make_unique<GpuTextures>(ctx, scene);

  if (s.method == IndirectMethod::Ldm) ldm_ = &ldmSource(dirs);
  gpu::IndirectConstants c{};
  c.directions = s.directions;
  c.resolution = s.ldmResolution;
  c.mapPixels = ldm_ ? ldm_->mapCount() * s.ldmResolution * s.ldmResolution : 0;
  c.ldmList = ldm_ ? uint32_t(ldm_->list()) : 0u;  // LdmList's values are the shaders' kLdmList*
  c.ldmCapacity = ldm_ ? ldm_->nodeCapacity() : 0;
  c.maxListSteps = ldm_ ? ldm_->nodeCapacity() : 1;
  c.biasScale = float(s.bias);
  c.side = s.photons;
  if (ldm_) c.ldmLinks = glm::uvec2(uint32_t(ldm_->links().address()), uint32_t(ldm_->links().address() >> 32));
  c.primaries = primaries_;
  c.samples = s.samples;
  c.samplesSide = uint32_t(std::lround(std::sqrt(double(s.samples))));
  c.faces = uint32_t(faces.size());
  {
    glm::vec3 lo, hi;
    scene.bounds(lo, hi);
    const double radius = std::max(0.5 * glm::length(glm::dvec3(hi) - glm::dvec3(lo)), 1e-6) * (1.0 + 1e-6);
    c.ldmPixel = float(2.0 * radius / s.ldmResolution);  // the LDM's pixel (ldmMaps), for both methods
    c.maxAnisotropy = float(s.maxAnisotropy);
    c.bounces = s.bounces;
    c.bounceDirections = s.bounceDirections;
    c.footprint = s.cellFootprint ? gpu::kFootprintCell : gpu::kFootprintRotated;
    ldmPixel_ = c.ldmPixel;
  }
  params_ = uploadBuffer(ctx, &c, sizeof c, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, MemClass::Other);

  rayQuery_ = settings.tracer && settings.tracer->rayQuery() && ctx.info().rayQuery;
  const bool needsHits = settings.worldPos == WorldPosMethod::Hit || settings.normals == NormalCulling::Geometric;
  HB_ASSERT(!needsHits || (in.hitIds && in.hitRays && in.hitTriangles));

  const bool splatCompute = s.method != IndirectMethod::Reference && s.splat == IndirectSplat::Compute;
  // The trace, the gather and the splat share one set per target (makeTarget), laid out from all
  // their shaders together: the tracer's, the raster splat's and, with splat=compute, its own.
  std::vector<std::string> shaders =
      settings_.computeBvh() ? std::vector<std::string>{"indirect_computetrace.comp"}
      : rayQuery_            ? std::vector<std::string>{"indirect.comp"}
                             : std::vector<std::string>{"indirect.rgen", "indirect.rmiss", "indirect.rchit"};
  shaders.insert(shaders.end(), {"photon_splat.vert", "photon_splat.frag"});
  if (splatCompute)
    shaders.insert(shaders.end(), {"photon_splat_bin.comp", "photon_splat.comp", "photon_splat_count.comp"});
  shaders_ = std::make_unique<ShaderProgram>(shaders);
  if (splatCompute) setUpComputeSplat(width, height, props);
  frame_ = makeTarget(s.method != IndirectMethod::Reference);
  createComputeSplatPipelines();
  splat_.createLayout({frame_.sets->layout()}, 0);
  {
    ShaderModule vert(ctx, shaders_->spirv("photon_splat.vert")), frag(ctx, shaders_->spirv("photon_splat.frag"));
    const SpecConstants spec{{uint32_t(settings.normals), uint32_t(settings.worldPos)}};
    std::vector<VkSpecializationMapEntry> entries;
    const VkSpecializationInfo si = specializationInfo(spec, entries);
    RasterPipelineDesc desc;
    desc.layout = splat_.layout();
    desc.vertex = vert.handle();
    desc.fragment = frag.handle();
    desc.fragmentSpec = &si;
    desc.vertexAttributes = 0;
    desc.depthTest = false;
    desc.colorFormats = {kIrradianceFormat};
    desc.additiveBlend = true;
    splat_.pipeline_ = createRasterPipeline(ctx, desc);
    splat_.bindPoint_ = VK_PIPELINE_BIND_POINT_GRAPHICS;
  }
  for (uint32_t b = 1; b <= (s.method == IndirectMethod::Reference ? 1 : s.bounces); ++b)
    program(s.method, b);  // the frame's own, created up front
}

IndirectPass::~IndirectPass() = default;

IndirectPass::Target IndirectPass::makeTarget(bool withPhotons) {
  Target t;
  if (withPhotons)
    t.photons = Buffer(ctx_, slots() * sizeof(gpu::Photon),
                       VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT, false, MemClass::Other);
  t.irradiance = Image(ctx_, width_, height_, kIrradianceFormat,
                       VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT |
                           VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                       VK_IMAGE_ASPECT_COLOR_BIT);
  // splat=compute: the later bounces at their receivers (later_bounce_stride f > 1), else a texel.
  const uint32_t f = computeSplat_ && computeSplat_->hasLate ? computeSplat_->stride : 0;
  if (computeSplat_)
    t.late = Image(ctx_, f ? (width_ + f - 1) / f : 1, f ? (height_ + f - 1) / f * computeSplat_->parts : 1,
                   kIrradianceFormat, VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                   VK_IMAGE_ASPECT_COLOR_BIT);
  ctx_.submitAndWait(
      [&](VkCommandBuffer cmd) {
        Sync sync;
        VkClearColorValue zero{};
        VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        for (const Image* img : {&t.irradiance, &t.late}) {
          if (!img->handle()) continue;
          sync.use(cmd, {{*img, access::kFill.in(VK_IMAGE_LAYOUT_GENERAL).discarding()}});
          vkCmdClearColorImage(cmd, img->handle(), VK_IMAGE_LAYOUT_GENERAL, &zero, 1, &range);
        }
      },
      "clearing the indirect light's target");
  DescriptorBinder binder("indirect");
  binder.provide("Frame", *in_.frameConstants);
  binder.provide("Lights", *in_.lights);
  binder.provide("depthTex", *in_.depth, depthReadLayout(*in_.depth), in_.sampler);
  if (const TraceBvh* bvh = settings_.computeBvh()) {  // our traversal gives draw-order ids itself
    binder.provide("BvhNodes", bvh->nodes);
    binder.provide("BvhTriangles", bvh->triangles);
  } else {
    binder.provide("tlas", in_.tlas);
    binder.provide("IdBase", idBase_);
  }
  binder.provide("Positions", gpuScene_.vertices());
  binder.provide("SceneIndices", gpuScene_.indices());
  binder.provide("Materials", textures_->materials());
  binder.provide("Draws", draws_);
  binder.provide("TriangleDraws", triangleDraw_);
  provideSurfaceHits(binder, in_, placeholder_);
  binder.provide("Directions", directions_);
  binder.provide("LdmMaps", ldm_ ? ldm_->mapsBuffer() : placeholder_);
  binder.provide("Photons", withPhotons ? t.photons : placeholder_);
  binder.provide("Params", params_);
  binder.provide("Faces", faces_);
  binder.provide("irradianceImage", t.irradiance, VK_IMAGE_LAYOUT_GENERAL);
  binder.provide("textures", textures_->images(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, textures_->sampler());
  if (const ComputeSplat* cs = computeSplat_.get()) {
    binder.provide("Boxes", cs->boxes);
    binder.provide("Coarse", cs->coarse);
    binder.provide("Counts", cs->counts);
    binder.provide("Bins", cs->bins);
    binder.provide("List", cs->list);
    binder.provide("lateIrradiance", t.late, VK_IMAGE_LAYOUT_GENERAL);
    binder.provide("SplatWork", cs->work);
  }
  t.sets = binder.write(ctx_, *shaders_);
  binder.checkEveryNameRead();
  return t;
}

uint64_t IndirectPass::bounceSlots(uint32_t bounce) const {
  uint64_t n = uint64_t(primaries_) * settings_.indirect.directions;
  for (uint32_t b = 2; b <= bounce; ++b) n *= settings_.indirect.directionsAtBounce(b);
  return n;
}

uint64_t IndirectPass::bounceFirstSlot(uint32_t bounce) const {
  uint64_t first = 0;
  for (uint32_t b = 1; b < bounce; ++b) first += bounceSlots(b);
  return first;
}

const IndirectPass::Program& IndirectPass::program(IndirectMethod method, uint32_t bounce) {
  auto it = programs_.find({method, bounce});
  if (it != programs_.end()) return *it->second;
  HB_ASSERT(method != IndirectMethod::Ldm || ldm_);
  auto p = std::make_unique<Program>(ctx_);
  const uint32_t m = method == IndirectMethod::Ldm         ? gpu::kIndirectLdm
                     : method == IndirectMethod::RayTraced ? gpu::kIndirectRayTraced
                                                           : gpu::kIndirectReference;
  const SpecConstants spec{{uint32_t(settings_.normals), uint32_t(settings_.worldPos), m, bounce}};
  if (const TraceBvh* bvh = settings_.computeBvh()) {  // 64 threads a group
    SpecConstants withStack = spec;
    for (uint32_t v : traceBvhSpec(*bvh, 64, true)) withStack.values.push_back(v);
    p->compute.createLayout({frame_.sets->layout()}, 0);
    p->compute.createCompute(*shaders_, "indirect_computetrace.comp", withStack);
  } else if (rayQuery_) {
    p->compute.createLayout({frame_.sets->layout()}, 0);
    p->compute.createCompute(*shaders_, "indirect.comp", spec);
  } else {
    p->rt = std::make_unique<RaygenMissPipeline>(ctx_, frame_.sets->layout(), *shaders_, "indirect.rgen",
                                                 "indirect.rmiss", spec, "indirect.rchit");
  }
  return *programs_.emplace(std::pair{method, bounce}, std::move(p)).first->second;
}

// count: primary photons, kPhotonLanes threads each (indirect_common.glsl.inc: a 64-thread group a
// photon in compute, a launch of (64, count) in the pipeline), or pixels, a thread each (64 a group,
// or a launch of the image).
void IndirectPass::recordDispatch(VkCommandBuffer cmd, const Program& p, const Target& t, uint32_t count,
                                  bool pixels) const {
  constexpr uint32_t kPhotonLanes = 64;  // indirect_common.glsl.inc
  VkDescriptorSet set = t.sets->set();
  const Pipeline& pl = p.pipeline();
  vkCmdBindPipeline(cmd, pl.bindPoint(), pl.handle());
  vkCmdBindDescriptorSets(cmd, pl.bindPoint(), pl.layout(), 0, 1, &set, 0, nullptr);
  if (p.rt) {
    if (pixels)
      p.rt->traceRays(cmd, width_, height_);
    else
      p.rt->traceRays(cmd, kPhotonLanes, count);
  } else {
    const uint32_t groups = pixels ? (count + 63) / 64 : count, gx = std::min<uint32_t>(groups, 65535u);
    vkCmdDispatch(cmd, gx, (groups + gx - 1) / gx, 1);
  }
}

void IndirectPass::recordTraceInto(VkCommandBuffer cmd, Sync& sync, IndirectMethod method, const Target& t) const {
  // The trace programs share indirect_common.glsl.inc's bindings with the gather, so the
  // irradiance image is statically used by them: declared written, the splat after it waits.
  sync.use(cmd, {{t.photons, access::kRayWrite}, {t.irradiance, access::kRayWrite}});
  recordDispatch(cmd, *programs_.at({method, 1u}), t, primaries_, false);
  // Bounces 2..K: a thread per slot, 64 a group (a 64-lane launch row in the pipeline); each
  // retraces its chain, so the dispatches do not depend on each other.
  for (uint32_t b = 2; b <= settings_.indirect.bounces; ++b) {
    const uint64_t groups = (bounceSlots(b) + 63) / 64;
    HB_ASSERT(groups <= 0xFFFFFFFFull);
    sync.use(cmd, {{t.photons, access::kRayWrite}});  // other slots, but one buffer to the layers
    recordDispatch(cmd, *programs_.at({method, b}), t, uint32_t(groups), false);
  }
}

void IndirectPass::recordGatherInto(VkCommandBuffer cmd, Sync& sync, const Program& p, const Target& t) const {
  sync.use(cmd, {{t.irradiance, access::kRayWrite}});
  recordDispatch(cmd, p, t, width_ * height_, true);
}

void IndirectPass::recordSplatInto(VkCommandBuffer cmd, Sync& sync, const Target& t, GpuTimer* timer,
                                   bool analysis) const {
  if (computeSplat_) {
    recordComputeSplat(cmd, sync, t, timer, analysis);
    return;
  }
  // A quad per photon, blended into the target (an attachment in GENERAL, as the shaders bind it).
  sync.use(
      cmd,
      {{t.photons,
        {VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_READ_BIT}},
       {t.irradiance, access::kColorAttachment.in(VK_IMAGE_LAYOUT_GENERAL)}});
  VkRenderingAttachmentInfo ca{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  ca.imageView = t.irradiance.view();
  ca.imageLayout = VK_IMAGE_LAYOUT_GENERAL;
  ca.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  ca.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  VkRenderingInfo ri{VK_STRUCTURE_TYPE_RENDERING_INFO};
  ri.renderArea = {{0, 0}, {width_, height_}};
  ri.layerCount = 1;
  ri.colorAttachmentCount = 1;
  ri.pColorAttachments = &ca;
  vkCmdBeginRendering(cmd, &ri);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, splat_.handle());
  VkDescriptorSet set = t.sets->set();
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, splat_.layout(), 0, 1, &set, 0, nullptr);
  VkViewport vp{0, 0, float(width_), float(height_), 0, 1};
  VkRect2D sc{{0, 0}, {width_, height_}};
  vkCmdSetViewport(cmd, 0, 1, &vp);
  vkCmdSetScissor(cmd, 0, 1, &sc);
  // One draw over every slot in slot order (6 vertices each): deterministic blending.
  const uint64_t vertices = slots() * 6;
  HB_ASSERT(vertices <= 0xFFFFFFFFull);
  vkCmdDraw(cmd, uint32_t(vertices), 1, 0, 0);
  vkCmdEndRendering(cmd);
}

void IndirectPass::recordTrace(VkCommandBuffer cmd, Sync& sync) const { recordTraceInto(cmd, sync, method(), frame_); }
void IndirectPass::recordSplat(VkCommandBuffer cmd, Sync& sync, GpuTimer* timer, bool analysis) const {
  recordSplatInto(cmd, sync, frame_, timer, analysis);
}
void IndirectPass::recordGather(VkCommandBuffer cmd, Sync& sync) const {
  recordGatherInto(cmd, sync, *programs_.at({IndirectMethod::Reference, 1u}), frame_);
}

static std::vector<float> readRgba(const VulkanContext& ctx, const Image& img) {
  const std::vector<uint8_t> bytes = readbackImage(ctx, img, VK_IMAGE_LAYOUT_GENERAL, 16);
  std::vector<float> out(bytes.size() / sizeof(float));
  std::memcpy(out.data(), bytes.data(), out.size() * sizeof(float));
  return out;
}

static std::vector<gpu::Photon> readSlots(const VulkanContext& ctx, const Buffer& b) {
  const std::vector<uint8_t> bytes = readbackBuffer(ctx, b);
  std::vector<gpu::Photon> out(bytes.size() / sizeof(gpu::Photon));
  std::memcpy(out.data(), bytes.data(), out.size() * sizeof(gpu::Photon));
  return out;
}

std::vector<float> IndirectPass::readIrradiance() const { return readRgba(ctx_, frame_.irradiance); }

std::vector<gpu::Photon> IndirectPass::readPhotons() const {
  HB_ASSERT(method() != IndirectMethod::Reference);
  return readSlots(ctx_, frame_.photons);
}

std::vector<float> IndirectPass::computeWith(IndirectMethod m, std::vector<gpu::Photon>* photons) {
  if (m == method()) {
    if (photons && m != IndirectMethod::Reference) *photons = readPhotons();
    return readIrradiance();
  }
  HB_ASSERT(m != IndirectMethod::Ldm);
  if (!scratch_.sets) scratch_ = makeTarget(true);
  const Program& p = program(m);
  for (uint32_t b = 2; m != IndirectMethod::Reference && b <= settings_.indirect.bounces; ++b) program(m, b);
  if (m == IndirectMethod::Reference) {
    ctx_.submitAndWait(
        [&](VkCommandBuffer cmd) {
          Sync sync;
          recordGatherInto(cmd, sync, p, scratch_);
        },
        "the gathered indirect light");
  } else {
    ctx_.submitAndWait(
        [&](VkCommandBuffer cmd) {
          Sync sync;
          recordTraceInto(cmd, sync, m, scratch_);
          recordSplatInto(cmd, sync, scratch_, nullptr);
        },
        "the ray-traced photons");
    if (photons) *photons = readSlots(ctx_, scratch_.photons);
  }
  return readRgba(ctx_, scratch_.irradiance);
}

IndirectMemory IndirectPass::memory() const {
  IndirectMemory m;
  if (ldm_) m.ldmBytes = ldm_->memoryBytes();
  m.photonBytes = frame_.photons.size();
  if (computeSplat_) m.splatBytes = computeSplat_->bytes() + uint64_t(frame_.late.width()) * frame_.late.height() * 16;
  m.faceBytes = faces_.size();
  m.directionBytes = directions_.size();
  m.targetBytes = uint64_t(width_) * height_ * 16;
  for (const Image& img : textures_->images()) m.textureBytes += uint64_t(img.width()) * img.height() * 4;
  return m;
}

}  // namespace hb
