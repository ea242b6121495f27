#include "effects/indirect/indirect_pass.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "base/errors.h"
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

// splat=compute (photon_splat_bin.comp.glsl, photon_splat.comp.glsl): per slot its pixel box and
// coarse box, per (bin, chunk) a count and then its start, per bin its list's range, and the list.
// With later_bounce_stride f > 1 the boxes step covers every slot (`all`), the later bounces' slots
// are binned and gathered at stride f into the target's `late` image (`late`), then the first
// bounce's (`constants`), whose gather adds `late` interpolated.
struct IndirectPass::ComputeSplat {
  gpu::SplatConstants constants{}, all{}, late{};
  bool hasLate = false;
  uint32_t stride = 1;  // the later run's (later_bounce_stride)
  uint32_t parts = 1;   // the later run's gather: workgroups a tile (photon_splat.comp.glsl PARTS)
  Buffer boxes, coarse, counts, bins, list;
  Buffer work;  // analysis frames: each gather tile's (tests, terms), the later run's tiles first
  std::vector<std::unique_ptr<Pipeline>> bin;  // MODE 0..5
  // The gathers: [run][COUNT], run 0 the first bounce's (or every bounce's), 1 the later bounces';
  // COUNT 0 in timed frames, 1 in analysis frames.
  std::unique_ptr<Pipeline> gather[2][2];
  explicit ComputeSplat(const VulkanContext&) {}
  uint64_t bytes() const {
    return boxes.size() + coarse.size() + counts.size() + bins.size() + list.size() + work.size();
  }
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
  if (splatCompute) {
    if (!ctx.info().computeSubgroupBallot)
      throw InputError("effects.indirect.splat=compute needs subgroup ballots in compute shaders, which device \"" +
                       ctx.info().name + "\" lacks; use effects.indirect.splat=raster");
    auto cs = std::make_unique<ComputeSplat>(ctx);
    gpu::SplatConstants& k = cs->constants;
    HB_ASSERT(slots() <= 0xFFFFFFFFull);
    k.slots = uint32_t(slots());
    k.chunks = uint32_t((slots() + gpu::kSplatChunk - 1) / gpu::kSplatChunk);
    k.binPixels = s.splatBin;
    k.binsX = (width + k.binPixels - 1) / k.binPixels;
    k.binsY = (height + k.binPixels - 1) / k.binPixels;
    k.tilesX = (width + gpu::kSplatTile - 1) / gpu::kSplatTile;
    k.tilesY = (height + gpu::kSplatTile - 1) / gpu::kSplatTile;
    if (k.binsX > 255 || k.binsY > 255)
      throw InputError("effects.indirect.splat_bin=" + std::to_string(k.binPixels) + ": a " + std::to_string(width) +
                       "x" + std::to_string(height) +
                       " image has more than 255 bins a side, more than their 8-bit "
                       "coordinates hold; raise splat_bin or use splat=raster");
    // The list: room for every slot in 4 bins (the atrium's Fig. 10 photons reach about 1.3 of the
    // 128-pixel bins each). A bin whose entries would not fit is gathered from every slot instead:
    // slower, the same sum (photon_splat_bin.comp.glsl).
    const uint64_t maxEntries = props.limits.maxStorageBufferRange / 4;
    k.capacity = uint32_t(std::min<uint64_t>(std::max<uint64_t>(4 * slots(), 1u << 16), maxEntries));
    cs->all = k;
    // later_bounce_stride f > 1: two runs over the one set of bins and list, the later bounces' slots
    // at stride f, then the first bounce's.
    if (s.laterBounceStride > 1 && s.bounces > 1) {
      const uint32_t f = s.laterBounceStride;
      HB_ASSERT(f * gpu::kSplatTile <= k.binPixels);  // readIndirect checked
      cs->hasLate = true;
      gpu::SplatConstants& l = cs->late;
      l = k;
      l.first = uint32_t(bounceFirstSlot(2));
      l.slots = k.slots - l.first;
      l.chunks = (l.slots + gpu::kSplatChunk - 1) / gpu::kSplatChunk;
      cs->stride = f;
      l.tilesX = ((width + f - 1) / f + gpu::kSplatTile - 1) / gpu::kSplatTile;
      l.tilesY = ((height + f - 1) / f + gpu::kSplatTile - 1) / gpu::kSplatTile;
      // Enough workgroups to fill a large GPU (2,048: 132 SMs' worth of 16 resident ones on an H200)
      // though a coarse image has few tiles; each part of a tile's list is summed apart, then in order.
      cs->parts = std::clamp((2048u + l.tilesX * l.tilesY - 1) / (l.tilesX * l.tilesY), 1u, 16u);
      k.slots = l.first;
      k.chunks = (k.slots + gpu::kSplatChunk - 1) / gpu::kSplatChunk;
    }
    k.workBase = cs->hasLate ? cs->late.tilesX * cs->late.tilesY * cs->parts : 0;
    for (gpu::SplatConstants* run : {&k, &cs->late, &cs->all})
      run->rowBins = splatRowBins(run->chunks, run->binsX, run->binsY);
    const VkBufferUsageFlags use = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    cs->boxes = Buffer(ctx, std::max<uint64_t>(8, slots() * 8), use, false, MemClass::Other);
    const VkBufferUsageFlags readable = use | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;  // readSplatBins
    cs->coarse = Buffer(ctx, std::max<uint64_t>(4, slots() * 4), readable, false, MemClass::Other);
    cs->counts =
        Buffer(ctx, uint64_t(k.binsX) * k.binsY * std::max(k.chunks, cs->late.chunks) * 4, use, false, MemClass::Other);
    cs->bins = Buffer(ctx, uint64_t(k.binsX) * k.binsY * 16, readable, false, MemClass::Other);
    cs->list = Buffer(ctx, uint64_t(k.capacity) * 4, readable | VK_BUFFER_USAGE_TRANSFER_DST_BIT, false,
                      MemClass::Other);  // filled by tests (fillSplatList)
    cs->work = Buffer(ctx, (uint64_t(k.workBase) + uint64_t(k.tilesX) * k.tilesY) * 8,
                      use | VK_BUFFER_USAGE_TRANSFER_SRC_BIT, false, MemClass::Other);
    computeSplat_ = std::move(cs);
  }
  frame_ = makeTarget(s.method != IndirectMethod::Reference);
  if (ComputeSplat* cs = computeSplat_.get()) {
    for (uint32_t mode = 0; mode < 6; ++mode) {
      auto p = std::make_unique<Pipeline>(ctx);
      p->createLayout({frame_.sets->layout()}, sizeof(gpu::SplatConstants));
      p->createCompute(*shaders_, "photon_splat_bin.comp", SpecConstants{{mode}});
      cs->bin.push_back(std::move(p));
    }
    for (uint32_t run = 0; run < (cs->hasLate ? 2u : 1u); ++run)
      for (uint32_t count : {0u, 1u}) {
        // STRIDE, LATE: the first bounce's run adds the later bounces' (1, f); theirs (f, 1).
        const uint32_t stride = run ? cs->stride : 1u, late = run || !cs->hasLate ? 1u : cs->stride;
        auto g = std::make_unique<Pipeline>(ctx);
        g->createLayout({frame_.sets->layout()}, sizeof(gpu::SplatConstants));
        g->createCompute(
            *shaders_, count ? "photon_splat_count.comp" : "photon_splat.comp",
            SpecConstants{{uint32_t(settings.normals), uint32_t(settings.worldPos), count, stride, late, cs->parts}});
        cs->gather[run][count] = std::move(g);
      }
  }
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

// Boxes, counts, starts, lists, then the gather (photon_splat_bin.comp.glsl, photon_splat.comp.glsl),
// each step reading what the one before wrote.
// With later_bounce_stride f > 1, the later bounces' count, scan, fill and gather come first, named
// "photon_splat.later.*".
std::vector<std::string> IndirectPass::splatSubPasses() const {
  if (!computeSplat_) return {};
  std::vector<std::string> names = {"photon_splat.boxes"};
  if (computeSplat_->hasLate)
    names.insert(names.end(), {"photon_splat.later.count", "photon_splat.later.scan", "photon_splat.later.fill",
                               "photon_splat.later.gather"});
  names.insert(names.end(), {"photon_splat.count", "photon_splat.scan", "photon_splat.fill", "photon_splat.gather"});
  return names;
}

void IndirectPass::recordComputeSplat(VkCommandBuffer cmd, Sync& sync, const Target& t, GpuTimer* timer,
                                      bool analysis) const {
  using namespace access;
  const ComputeSplat& cs = *computeSplat_;
  // Each step reads the photons and what the steps before it wrote, and updates the bins; a gather
  // writes the target (the later bounces' gather its `late` image, which the last one reads).
  std::vector<Use> step = {{t.photons, kComputeRead},  {cs.boxes, kComputeWrite}, {cs.coarse, kComputeWrite},
                           {cs.counts, kComputeWrite}, {cs.bins, kComputeWrite},  {cs.list, kComputeWrite}};
  const VkDescriptorSet set = t.sets->set();
  const std::vector<std::string> names = splatSubPasses();
  size_t next = 0;
  auto dispatch = [&](const Pipeline& p, const gpu::SplatConstants& k, uint32_t x, uint32_t y,
                      std::vector<Use> extra = {}, uint32_t z = 1) {
    std::vector<Use> uses = step;
    uses.insert(uses.end(), extra.begin(), extra.end());
    sync.use(cmd, uses);
    if (timer) timer->begin(cmd, names[next]);
    ++next;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.handle());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.layout(), 0, 1, &set, 0, nullptr);
    vkCmdPushConstants(cmd, p.layout(), VK_SHADER_STAGE_ALL, 0, sizeof k, &k);
    vkCmdDispatch(cmd, x, y, z);
    if (timer) timer->end(cmd);
  };
  const uint32_t slotGroups = (cs.all.slots + 255) / 256, gx = std::max(1u, std::min(slotGroups, 65535u));
  dispatch(*cs.bin[0], cs.all, gx, (slotGroups + gx - 1) / gx);
  if (analysis) step.push_back({cs.work, kComputeWrite});
  auto run = [&](uint32_t r, const gpu::SplatConstants& k, std::vector<Use> gatherUses) {
    const uint32_t rows = (k.binsX + k.rowBins - 1) / k.rowBins * k.binsY;  // rowBins bins a group
    const bool single = k.rowBins == 1;                                     // MODE 4, 5: a single bin's loops
    dispatch(*cs.bin[single ? 4 : 1], k, k.chunks, rows);
    dispatch(*cs.bin[2], k, 1, 1);
    dispatch(*cs.bin[single ? 5 : 3], k, k.chunks, rows);
    dispatch(*cs.gather[r][analysis ? 1 : 0], k, k.tilesX, k.tilesY, std::move(gatherUses), r ? cs.parts : 1u);
  };
  if (cs.hasLate) run(1, cs.late, {{t.late, kComputeWrite}});
  std::vector<Use> last = {{t.irradiance, kComputeWrite}};
  if (cs.hasLate) last.push_back({t.late, kComputeRead});
  run(0, cs.constants, std::move(last));
  HB_ASSERT(next == names.size());
  if (analysis) splatCounted_ = true;
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

// A count or fill group reads each slot's coarse box once for rowBins bins of a row. The widest row
// that leaves 512 groups (about 4 of 256 threads for each of an H200's 132 SMs); a run of few chunks
// (the first bounce's at a stride) needs the groups more than the shared reads, since a group's 256
// rounds are then the step's time (measured on the H200: results/h200/raster3d-52/splat-rows).
uint32_t IndirectPass::splatRowBins(uint64_t chunks, uint32_t binsX, uint32_t binsY) {
  for (uint32_t r = gpu::kSplatBinRow; r > 1; r /= 2)
    if (chunks * ((binsX + r - 1) / r) * binsY >= 512) return r;
  return 1;
}

void IndirectPass::forceSplatRowBins(uint32_t rowBins) {
  HB_ASSERT(computeSplat_ && rowBins >= 1 && rowBins <= gpu::kSplatBinRow && (rowBins & (rowBins - 1)) == 0);
  for (gpu::SplatConstants* run : {&computeSplat_->constants, &computeSplat_->late, &computeSplat_->all})
    run->rowBins = rowBins;
}

void IndirectPass::fillSplatList(uint32_t value) {
  HB_ASSERT(computeSplat_);
  ctx_.submitAndWait(
      [&](VkCommandBuffer cmd) { vkCmdFillBuffer(cmd, computeSplat_->list.handle(), 0, VK_WHOLE_SIZE, value); },
      "the splat list filled for a test");
}

nlohmann::json IndirectPass::splatPipelineStatistics() const {
  if (!computeSplat_ || !ctx_.info().pipelineStatistics) return nullptr;
  const ComputeSplat& cs = *computeSplat_;
  nlohmann::json j = {{"count", pipelineStatistics(ctx_, cs.bin[1]->handle())},
                      {"fill", pipelineStatistics(ctx_, cs.bin[3]->handle())},
                      {"gather", pipelineStatistics(ctx_, cs.gather[0][0]->handle())}};
  if (cs.hasLate) j["later.gather"] = pipelineStatistics(ctx_, cs.gather[1][0]->handle());
  return j;
}

std::optional<IndirectPass::SplatBins> IndirectPass::readSplatBins() const {
  if (!computeSplat_) return std::nullopt;
  const gpu::SplatConstants& k = computeSplat_->constants;  // the last run: the first bounce's, or all
  SplatBins out;
  out.binsX = k.binsX;
  out.binsY = k.binsY;
  out.first = k.first;
  out.slots = k.slots;
  out.capacity = k.capacity;
  auto words = [this](const Buffer& b) {
    const std::vector<uint8_t> bytes = readbackBuffer(ctx_, b);
    std::vector<uint32_t> w(bytes.size() / 4);
    std::memcpy(w.data(), bytes.data(), w.size() * 4);
    return w;
  };
  out.coarse = words(computeSplat_->coarse);
  const std::vector<uint32_t> bins = words(computeSplat_->bins);
  uint64_t entries = 0;
  for (size_t b = 0; b + 3 < bins.size(); b += 4) {
    out.bins.push_back({bins[b], bins[b + 1], bins[b + 2]});
    entries = std::max<uint64_t>(entries, uint64_t(bins[b]) + bins[b + 1]);
  }
  out.list = words(computeSplat_->list);
  out.list.resize(std::min<uint64_t>(entries, out.list.size()));
  return out;
}

std::optional<IndirectPass::SplatStats> IndirectPass::splatStats() const {
  if (!computeSplat_) return std::nullopt;
  const std::vector<uint8_t> bytes = readbackBuffer(ctx_, computeSplat_->bins);
  SplatStats st;
  st.bins = bytes.size() / 16;
  st.capacity = computeSplat_->constants.capacity;
  for (size_t b = 0; b < st.bins; ++b) {
    uint32_t v[4];
    std::memcpy(v, bytes.data() + 16 * b, sizeof v);
    st.entries += v[1];
    st.overCapacity += v[2] == 0;
  }
  st.counted = splatCounted_;
  if (st.counted) {
    const std::vector<uint8_t> work = readbackBuffer(ctx_, computeSplat_->work);
    const uint32_t firstTile = computeSplat_->constants.workBase;
    for (size_t i = 0; i < work.size() / 8; ++i) {
      uint32_t v[2];
      std::memcpy(v, work.data() + 8 * i, sizeof v);
      (i < firstTile ? st.laterTests : st.tests) += v[0];
      (i < firstTile ? st.laterTerms : st.terms) += v[1];
    }
  }
  return st;
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
