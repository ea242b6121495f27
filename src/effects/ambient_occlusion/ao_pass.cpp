#include "effects/ambient_occlusion/ao_pass.h"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "base/errors.h"
#include "frame/passes/depth_prepass.h"
#include "gpu/descriptor_binder.h"
#include "reference/eq_partition.h"
#include "reference/ldm_ref.h"
#include "scene/environment.h"
#include "shared/gpu_types.h"

namespace hb {

struct AoPass::Program {
  Pipeline compute;
  std::unique_ptr<RaygenMissPipeline> rt;
  std::unique_ptr<DescriptorSets> scratch;  // its set over the scratch output (computeWith), where it traces
  explicit Program(const VulkanContext& c) : compute(c) {}
  const Pipeline& pipeline() const { return rt ? rt->pipeline() : compute; }
};

AoPass::AoPass(const VulkanContext& ctx, const Scene& scene, const AoPassSettings& settings, uint32_t width,
               uint32_t height, const AoInputs& in, const LdmSource& ldmSource)
    : ctx_(ctx), settings_(settings), width_(width), height_(height), tlas_(in.tlas) {
  const AoSettings& ao = settings.ao;
  const Environment* env = settings.environment;
  const std::string effect = std::string("effects.") + settings.effect;
  if ((ao.method == AoMethod::RayTraced || ao.method == AoMethod::Reference) && !tlas_)
    throw InputError(effect + ".method=" + toString(ao.method) + " needs the ray tracer, which this frame has not (" +
                     (env ? "turn shadows on, or use method ldm)" : "use method ldm, hbao or gtao)"));
  HB_ASSERT(!env || ao.method == AoMethod::Ldm || ao.method == AoMethod::RayTraced || ao.method == AoMethod::Reference);
  std::vector<glm::dvec3> dirs;
  try {
    dirs = ldmDirections(ao.directions);
  } catch (const std::invalid_argument& e) {
    throw InputError(effect + ".directions: " + e.what());
  }
  std::vector<glm::vec4> packed;
  for (const glm::dvec3& d : dirs) packed.emplace_back(glm::vec3(d), 0.0f);
  if (env) {  // the radiance along +v_i, then along −v_i (ao_common.glsl.inc RADIANCE)
    for (double sign : {1.0, -1.0})
      for (const glm::dvec3& d : dirs) packed.emplace_back(glm::vec3(environmentRadiance(*env, sign * d)), 0.0f);
  }
  directions_ = uploadBuffer(ctx, packed.data(), packed.size() * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                             MemClass::Other);
  uint32_t maxSteps = 1;
  if (ao.method == AoMethod::Ldm) {
    ldm_ = &ldmSource(dirs);
    maxSteps = ldm_->nodeCapacity();
  }
  gpu::AoConstants c{};
  c.directions = ao.directions;
  c.resolution = ao.ldmResolution;
  c.mapPixels = ldm_ ? ldm_->mapCount() * ao.ldmResolution * ao.ldmResolution : 0;
  c.samples = ao.samples;
  c.samplesSide = uint32_t(std::lround(std::sqrt(double(ao.samples))));
  c.dMax = ao.dMax ? float(*ao.dMax) : 0.0f;
  c.biasScale = float(ao.bias);
  c.maxListSteps = maxSteps;
  c.hbaoSteps = ao.steps;
  {
    glm::vec3 lo, hi;
    scene.bounds(lo, hi);
    c.hbaoRadius = ao.dMax ? float(*ao.dMax) : std::max(0.5f * glm::length(hi - lo), 1e-6f);
  }
  if (env) {
    c.envWidth = env->width;
    c.envHeight = env->height;
    c.envScale = glm::vec4(env->color * env->intensity, 0.0f);
    const double a = double(env->rotationDegrees) * 3.14159265358979323846 / 180.0;
    c.envRotation = glm::vec4(float(std::cos(a)), float(std::sin(a)), 0.0f, 0.0f);
    std::vector<glm::vec4> texels;
    texels.reserve(env->texels.size());
    for (const glm::vec3& t : env->texels) texels.emplace_back(t, 0.0f);
    environment_ = uploadBuffer(ctx, texels.data(), texels.size() * sizeof(glm::vec4),
                                VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemClass::Other);
  }
  if (ldm_) {
    c.ldmLinks = glm::uvec2(uint32_t(ldm_->links().address()), uint32_t(ldm_->links().address() >> 32));
    c.ldmList = uint32_t(ldm_->list());  // LdmList's values are the shaders' kLdmList*
    c.ldmCapacity = ldm_->nodeCapacity();
  }
  params_ = uploadBuffer(ctx, &c, sizeof c, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, MemClass::Other);
  {
    gpu::AoConstants r = c;  // the analysis frame's reference (computeWith)
    r.samples = kAoReferenceSamples;
    r.samplesSide = uint32_t(std::lround(std::sqrt(double(kAoReferenceSamples))));
    scratchParams_ = uploadBuffer(ctx, &r, sizeof r, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, MemClass::Other);
  }
  const VkDeviceSize pixels = VkDeviceSize(width) * height;
  const VkBufferUsageFlags outUsage =
      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  const VkDeviceSize outBytes = pixels * sizeof(float) * (env ? 4 : 1);
  output_ = Buffer(ctx, outBytes, outUsage, false, MemClass::Other);
  placeholder_ = Buffer(ctx, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, MemClass::Other);

  const bool needsHits = settings.worldPos == WorldPosMethod::Hit || settings.normals == NormalCulling::Geometric;
  HB_ASSERT(!needsHits || (in.hitIds && in.hitRays && in.hitTriangles));
  auto provide = [&](DescriptorBinder& b, const Buffer& out, const Buffer& params) {
    b.provide("Frame", *in.frameConstants);
    b.provide("depthTex", *in.depth, depthReadLayout(*in.depth), in.sampler);
    if (const TraceBvh* bvh = settings.computeBvh()) {  // backend=compute traces our BVH, not the TLAS
      b.provide("BvhNodes", bvh->nodes);
      b.provide("BvhTriangles", bvh->triangles);
    } else if (tlas_) {
      b.provide("tlas", tlas_);
    }
    provideSurfaceHits(b, in, placeholder_);
    b.provide("AoDirections", directions_);
    b.provide("LdmMaps", ldm_ ? ldm_->mapsBuffer() : placeholder_);
    b.provide("AoOut", out);
    b.provide("AoParams", params);
    // Without an environment EnvironmentMap is never read (RADIANCE = 0).
    b.provide("EnvironmentMap", env ? environment_ : placeholder_);
  };
  binder_ = std::make_unique<DescriptorBinder>("ambient_occlusion");
  provide(*binder_, output_, params_);
  if (tlas_) {
    scratch_ = Buffer(ctx, outBytes, outUsage, false, MemClass::Other);
    scratchBinder_ = std::make_unique<DescriptorBinder>("ambient_occlusion.reference");
    provide(*scratchBinder_, scratch_, scratchParams_);
  }
  program(ao.method);  // the frame's own, created up front
  // With a tracer the reference's too (computeWith), so that every name provided is seen read.
  if (tlas_) program(AoMethod::Reference);
  binder_->checkEveryNameRead();
  if (scratchBinder_) scratchBinder_->checkEveryNameRead();
}

AoPass::~AoPass() = default;

const AoPass::Program& AoPass::program(AoMethod method) {
  auto it = programs_.find(method);
  if (it != programs_.end()) return *it->second;
  auto p = std::make_unique<Program>(ctx_);
  const uint32_t radiance = settings_.environment ? 1u : 0u;  // ao_common.glsl.inc RADIANCE
  if (method == AoMethod::Ldm || method == AoMethod::Hbao || method == AoMethod::Gtao) {
    HB_ASSERT(method != AoMethod::Ldm || ldm_);
    p->compute.createCompute(*binder_, "ao_compute.comp", 0,
                             SpecConstants{{uint32_t(settings_.normals), uint32_t(settings_.worldPos),
                                            method == AoMethod::Ldm    ? gpu::kAoLdm
                                            : method == AoMethod::Hbao ? gpu::kAoHbao
                                                                       : gpu::kAoGtao,
                                            radiance}});
  } else {
    HB_ASSERT(tlas_);
    const SpecConstants spec{{uint32_t(settings_.normals), uint32_t(settings_.worldPos),
                              method == AoMethod::Reference ? gpu::kAoReference : gpu::kAoRayTraced, radiance}};
    if (settings_.computeBvh()) {
      SpecConstants withStack = spec;
      for (uint32_t v : traceBvhSpec(*settings_.computeBvh(), 64, false)) withStack.values.push_back(v);  // 8x8 threads
      p->compute.createCompute(*binder_, "ao_computetrace.comp", 0, withStack);
      p->scratch = scratchBinder_->write(ctx_, ShaderProgram({"ao_computetrace.comp"}));
    } else if (ctx_.info().rayQuery) {
      p->compute.createCompute(*binder_, "ao_rayquery.comp", 0, spec);
      p->scratch = scratchBinder_->write(ctx_, ShaderProgram({"ao_rayquery.comp"}));
    } else {
      p->rt = std::make_unique<RaygenMissPipeline>(ctx_, *binder_, "ao.rgen", "shadows.rmiss", spec);
      p->scratch = scratchBinder_->write(ctx_, ShaderProgram({"ao.rgen", "shadows.rmiss"}));
    }
  }
  return *programs_.emplace(method, std::move(p)).first->second;
}

void AoPass::recordProgram(VkCommandBuffer cmd, const Program& p, bool scratch) const {
  const Pipeline& pl = p.pipeline();
  VkDescriptorSet set = scratch ? p.scratch->set() : pl.set();
  vkCmdBindPipeline(cmd, pl.bindPoint(), pl.handle());
  vkCmdBindDescriptorSets(cmd, pl.bindPoint(), pl.layout(), 0, 1, &set, 0, nullptr);
  if (p.rt)
    p.rt->traceRays(cmd, width_, height_);
  else
    vkCmdDispatch(cmd, (width_ + 7) / 8, (height_ + 7) / 8, 1);
}

void AoPass::recordAo(VkCommandBuffer cmd) const { recordProgram(cmd, *programs_.at(settings_.ao.method), false); }

static std::vector<float> readFloats(const VulkanContext& ctx, const Buffer& b) {
  const std::vector<uint8_t> bytes = readbackBuffer(ctx, b);
  std::vector<float> out(bytes.size() / sizeof(float));
  std::memcpy(out.data(), bytes.data(), out.size() * sizeof(float));
  return out;
}

std::vector<float> AoPass::readAo() const { return readFloats(ctx_, output_); }

std::vector<float> AoPass::computeWith(AoMethod method) {
  if (method == settings_.ao.method && (method != AoMethod::Reference || settings_.ao.isTheReference()))
    return readAo();
  HB_ASSERT((method == AoMethod::RayTraced || method == AoMethod::Reference) && tlas_);
  const Program& p = program(method);
  ctx_.submitAndWait([&](VkCommandBuffer cmd) { recordProgram(cmd, p, true); }, "an analysis reference");
  return readFloats(ctx_, scratch_);
}

AoMemory AoPass::memory() const {
  AoMemory m;
  if (ldm_) {
    m.ldmLinkBytes = ldm_->links().size();
    m.ldmMapBytes = ldm_->mapsBuffer().size();
  }
  m.directionBytes = directions_.size();
  m.outputBytes = output_.size();
  m.environmentBytes = settings_.environment ? environment_.size() : 0;
  return m;
}

}  // namespace hb
