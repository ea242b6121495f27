#include "frame/passes/ldm_build.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cstring>

#include "base/errors.h"
#include "gpu/descriptor_binder.h"
#include "gpu/raster_pipeline.h"
#include "reference/ldm_ref.h"

namespace hb {

namespace {
constexpr uint32_t kChunkGroups = 4096;
}  // namespace

LdmBuild::LdmBuild(const VulkanContext& ctx, const GpuScene& gpuScene, const Scene& scene,
                   std::vector<gpu::LdmMap> maps, uint32_t resolution, uint32_t nodeCapacity, LdmBuildMethod method,
                   LdmList list, LdmBuildTuning tuning)
    : ctx_(ctx),
      scene_(gpuScene),
      maps_(std::move(maps)),
      resolution_(resolution),
      nodeCapacity_(nodeCapacity),
      method_(method),
      list_(list),
      tuning_(tuning),
      mapsBuffer_(uploadBuffer(ctx, maps_.data(), maps_.size() * sizeof(gpu::LdmMap),
                               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemClass::Other)),
      links_(ctx,
             list == LdmList::Max64 ? (uint64_t(maps_.size()) * resolution * resolution + nodeCapacity) * 8
             : list == LdmList::Cas ? (uint64_t(maps_.size()) * resolution * resolution + 2ull * nodeCapacity) * 4
                                    : (2ull * maps_.size() * resolution * resolution + 1 + 2ull * nodeCapacity) * 4,
             VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                 VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
             false, MemClass::Other),
      counters_(
          ctx, gpu::kLdmCounterCount * sizeof(uint32_t),
          VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
          false, MemClass::Other),
      pipeline_(ctx) {
  HB_ASSERT(!maps_.empty() && resolution_ > 0 && nodeCapacity_ > 0);
  if (!ctx.info().bufferInt64Atomics || (method == LdmBuildMethod::Hardware && !ctx.info().fragmentSubgroupBallot))
    throw InputError("device \"" + ctx.info().name +
                     "\" lacks 64-bit buffer atomics or subgroup ballots in fragment "
                     "shaders, which the hardware LDM build needs: use effects.ambient_occlusion.method=raytraced");
  if (method == LdmBuildMethod::Raster3d && !ctx.info().shaderFloat64)
    throw InputError("device \"" + ctx.info().name +
                     "\" has no fp64 in shaders, which ldm_build=3dr needs at shared "
                     "vertices: use ldm_build=hardware");
  DescriptorBinder binder("ldm_build");
  binder.provide("Maps", mapsBuffer_);
  const glm::uvec2 address(uint32_t(links_.address()), uint32_t(links_.address() >> 32));
  linksAddress_ = uploadBuffer(ctx, &address, sizeof address, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, MemClass::Other);
  binder.provide("LinksAddress", linksAddress_);
  binder.provide("Counters", counters_);
  const uint32_t pixels = uint32_t(maps_.size()) * resolution_ * resolution_;
  const uint32_t listId = list == LdmList::Max64 ? gpu::kLdmListMax64
                          : list == LdmList::Cas ? gpu::kLdmListCas
                                                 : gpu::kLdmListSbuffer;
  // The chunk list: as asked, or 2·maps·R² entries (a build made without a counting build, as tests do).
  chunkCapacity_ = std::max<uint32_t>(1, tuning.chunkCapacity ? tuning.chunkCapacity : 2 * pixels);
  HB_ASSERT(tuning.chunkPixels >= 64 && tuning.chunkPixels % 64 == 0);
  auto specFor = [&](uint32_t phase, uint32_t mode) {
    return SpecConstants{{resolution_, nodeCapacity_, pixels, listId, phase, mode, tuning_.smallBox, chunkCapacity_,
                          tuning_.chunkPixels}};
  };
  if (method == LdmBuildMethod::Raster3d) {
    std::vector<glm::vec4> tris;
    for (const glm::vec3& v : scene.worldTriangles()) tris.emplace_back(v, 1.0f);
    triangleCount_ = uint32_t(tris.size() / 3);
    if ((uint64_t(triangleCount_) + 63) / 64 > 65535)  // the dispatch's x count (Vulkan's guaranteed minimum)
      throw InputError("ldm_build=3dr: " + std::to_string(triangleCount_) +
                       " triangles exceed one dispatch (4,194,240); "
                       "use ldm_build=hardware");
    if (tris.empty()) tris.emplace_back(0.0f);
    triangles_ = uploadBuffer(ctx, tris.data(), tris.size() * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                              MemClass::Geometry);
    binder.provide("Triangles", triangles_);
    chunks_ = Buffer(ctx, uint64_t(chunkCapacity_) * 8, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, MemClass::Other);
    binder.provide("Chunks", chunks_);
  }
  auto makeChunks = [&](uint32_t phase) {
    auto p = std::make_unique<Pipeline>(ctx);
    p->createCompute(binder, "ldm_build_3dr.comp", sizeof(uint32_t), specFor(phase, 1));
    return p;
  };
  auto makeBuild = [&](Pipeline& p, uint32_t phase) {
    if (method == LdmBuildMethod::Raster3d) {
      p.createCompute(binder, "ldm_build_3dr.comp", sizeof(uint32_t), specFor(phase, 0));
      return;
    }
    const ShaderProgram program({"ldm_build.vert", "ldm_build.frag"});
    p.createLayout(binder, program, sizeof(gpu::DrawConstants));
    ShaderModule vert(ctx, program.spirv(0)), frag(ctx, program.spirv(1));
    std::vector<VkSpecializationMapEntry> entries;
    const SpecConstants spec = specFor(phase, 0);
    VkSpecializationInfo si = specializationInfo(spec, entries);
    RasterPipelineDesc desc;
    desc.layout = p.layout();
    desc.vertex = vert.handle();
    desc.fragment = frag.handle();
    desc.fragmentSpec = &si;
    desc.depthTest = false;  // every crossing is stored, both faces (no culling: raster_pipeline.h)
    p.pipeline_ = createRasterPipeline(ctx, desc);
    p.bindPoint_ = VK_PIPELINE_BIND_POINT_GRAPHICS;
  };
  if (list != LdmList::Sbuffer) {
    makeBuild(pipeline_, gpu::kLdmPhaseInsert);
    if (method == LdmBuildMethod::Raster3d) insertChunks_ = makeChunks(gpu::kLdmPhaseInsert);
    binder.checkEveryNameRead();
    return;
  }
  makeBuild(pipeline_, gpu::kLdmPhaseCount);
  fill_ = std::make_unique<Pipeline>(ctx);
  makeBuild(*fill_, gpu::kLdmPhaseFill);
  if (method == LdmBuildMethod::Raster3d) {
    insertChunks_ = makeChunks(gpu::kLdmPhaseCount);
    fillChunks_ = makeChunks(gpu::kLdmPhaseFill);
  }
  const uint32_t blocks = (pixels + 4095) / 4096;
  blockSums_ = Buffer(ctx, std::max<uint32_t>(blocks, 1) * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false,
                      MemClass::Other);
  binder.provide("BlockSums", blockSums_);
  for (uint32_t stage = 0; stage < 4; ++stage) {
    scan_[stage] = std::make_unique<Pipeline>(ctx);
    scan_[stage]->createCompute(binder, "ldm_sbuffer.comp", 0,
                                SpecConstants{{stage, pixels, nodeCapacity_, stage == 1 ? 1024u : 256u}});
  }
  binder.checkEveryNameRead();
}

LdmBuild::~LdmBuild() = default;

std::vector<Use> LdmBuild::working(Access a) const {
  std::vector<Use> uses;
  for (const Buffer* b : {&links_, &counters_, &chunks_, &blockSums_}) uses.push_back({*b, a});
  return uses;
}

void LdmBuild::recordGeometry(VkCommandBuffer cmd, Sync& sync, const Pipeline& p, const Pipeline* chunks) const {
  VkDescriptorSet set = p.set();
  if (method_ == LdmBuildMethod::Raster3d) {
    sync.use(cmd, working(access::kComputeWrite));
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.handle());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.layout(), 0, 1, &set, 0, nullptr);
    vkCmdPushConstants(cmd, p.layout(), VK_SHADER_STAGE_ALL, 0, sizeof triangleCount_, &triangleCount_);
    if (triangleCount_ > 0) vkCmdDispatch(cmd, (triangleCount_ + 63) / 64, uint32_t(maps_.size()), 1);
    // The listed chunks (ldm_build_3dr.comp.glsl MODE 1): the pair pass's list, read after it.
    sync.use(cmd, working(access::kComputeWrite));
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, chunks->handle());
    set = chunks->set();
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, chunks->layout(), 0, 1, &set, 0, nullptr);
    vkCmdPushConstants(cmd, chunks->layout(), VK_SHADER_STAGE_ALL, 0, sizeof triangleCount_, &triangleCount_);
    // A grid-stride loop over the list: enough workgroups of 64 to fill a large GPU once.
    vkCmdDispatch(cmd, std::min<uint32_t>(kChunkGroups, chunkCapacity_), 1, 1);
  } else {  // the fragment shader builds the lists
    sync.use(cmd, working({VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, access::kShaderReadWrite}));
    VkRenderingInfo ri{VK_STRUCTURE_TYPE_RENDERING_INFO};
    ri.renderArea = {{0, 0}, {resolution_, resolution_}};
    ri.layerCount = 1;
    vkCmdBeginRendering(cmd, &ri);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p.handle());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p.layout(), 0, 1, &set, 0, nullptr);
    drawScene(cmd, scene_, p.layout(), glm::mat4(1.0f), resolution_, resolution_, uint32_t(maps_.size()));
    vkCmdEndRendering(cmd);
  }
}

std::vector<std::string> LdmBuild::subPasses(const std::string& pass) const {
  if (list_ != LdmList::Sbuffer) return {pass + ".insert"};
  return {pass + ".count", pass + ".scan", pass + ".fill", pass + ".sort"};
}

void LdmBuild::record(VkCommandBuffer cmd) const {
  Sync sync;
  record(cmd, sync);
}

void LdmBuild::record(VkCommandBuffer cmd, Sync& sync, GpuTimer* timer, const std::string& pass) const {
  const std::vector<std::string> steps = timer ? subPasses(pass) : std::vector<std::string>{};
  size_t step = 0;
  auto begin = [&] {
    if (timer) timer->begin(cmd, steps[step++]);
  };
  auto end = [&] {
    if (timer) timer->end(cmd);
  };
  // What must start at zero: sbuffer's counts and cursors, cas's heads (a node's next and depth are
  // written before it is linked), every max64 link (a node's next link is atomicMax'ed from 0).
  const uint64_t pixels = uint64_t(maps_.size()) * resolution_ * resolution_;
  const VkDeviceSize cleared = list_ == LdmList::Sbuffer ? (2 * pixels + 1) * 4
                               : list_ == LdmList::Cas   ? pixels * 4
                                                         : VK_WHOLE_SIZE;
  begin();
  sync.use(cmd, {{links_, access::kFill}, {counters_, access::kFill}});
  vkCmdFillBuffer(cmd, links_.handle(), 0, cleared, 0);
  vkCmdFillBuffer(cmd, counters_.handle(), 0, VK_WHOLE_SIZE, 0);
  recordGeometry(cmd, sync, pipeline_, insertChunks_.get());
  end();
  if (list_ != LdmList::Sbuffer) return;
  // Counts → offsets (three scan stages), the fill pass, then each range sorted.
  const uint32_t blocks = uint32_t((pixels + 4095) / 4096), groups = uint32_t((pixels + 255) / 256);
  auto stage = [&](uint32_t s, uint32_t x, uint32_t y) {
    VkDescriptorSet set = scan_[s]->set();
    sync.use(cmd, working(access::kComputeWrite));
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, scan_[s]->handle());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, scan_[s]->layout(), 0, 1, &set, 0, nullptr);
    vkCmdDispatch(cmd, x, y, 1);
  };
  begin();
  stage(0, blocks, 1);
  stage(1, 1, 1);
  stage(2, blocks, 1);
  end();
  begin();
  recordGeometry(cmd, sync, *fill_, fillChunks_.get());
  end();
  begin();
  stage(3, std::min<uint32_t>(groups, 1024), (groups + 1023) / 1024);
  end();
}

uint64_t LdmBuild::exactBytes(uint64_t fragments) const {
  const uint64_t heads = maps_.size() * uint64_t(resolution_) * resolution_;
  if (list_ == LdmList::Sbuffer) return 4 * (2 * heads + 1) + 8 * fragments;
  return (list_ == LdmList::Max64 ? 8 : 4) * heads + 8 * fragments;
}

namespace {
// Walks every list of a links buffer (gpu_types.h layouts), calling visit(pixel, depth) in order.
template <typename Visit>
void walkLists(const std::vector<uint8_t>& bytes, LdmList list, size_t pixels, uint32_t capacity, Visit visit) {
  if (list == LdmList::Max64) {
    const uint64_t* links = reinterpret_cast<const uint64_t*>(bytes.data());
    for (size_t p = 0; p < pixels; ++p) {
      uint64_t rec = links[p];
      // A list is at most the pool long; a longer walk would mean a cycle (never written).
      for (size_t n = 0; rec != 0 && n <= capacity; ++n) {
        const uint32_t node = uint32_t(rec & 0xFFFFFFFFu);
        HB_ASSERT(node >= 1 && node <= capacity);
        visit(p, std::bit_cast<float>(gpu::kLdmKeyTop - uint32_t(rec >> 32)));
        rec = links[pixels + node - 1];
      }
    }
    return;
  }
  const uint32_t* words = reinterpret_cast<const uint32_t*>(bytes.data());
  if (list == LdmList::Sbuffer) {
    for (size_t p = 0; p < pixels; ++p)
      for (uint32_t k = std::min(words[p], capacity); k < std::min(words[p + 1], capacity); ++k)
        visit(p, std::bit_cast<float>(words[2 * pixels + 1 + k]));
    return;
  }
  for (size_t p = 0; p < pixels; ++p) {
    uint32_t node = words[p];
    for (size_t n = 0; node != 0 && n <= capacity; ++n) {
      HB_ASSERT(node <= capacity);
      visit(p, std::bit_cast<float>(words[pixels + capacity + node - 1]));
      node = words[pixels + node - 1];
    }
  }
}
}  // namespace

std::vector<std::vector<float>> LdmBuild::readLists() const {
  const size_t pixels = maps_.size() * size_t(resolution_) * resolution_;
  std::vector<std::vector<float>> lists(pixels);
  walkLists(readbackBuffer(ctx_, links_), list_, pixels, nodeCapacity_,
            [&](size_t p, float depth) { lists[p].push_back(depth); });
  return lists;
}

std::vector<uint32_t> LdmBuild::readListLengths() const {
  const size_t pixels = maps_.size() * size_t(resolution_) * resolution_;
  std::vector<uint32_t> lengths(pixels, 0);
  walkLists(readbackBuffer(ctx_, links_), list_, pixels, nodeCapacity_, [&](size_t p, float) { ++lengths[p]; });
  return lengths;
}

LdmCounters LdmBuild::readCounters() const {
  const std::vector<uint8_t> bytes = readbackBuffer(ctx_, counters_);
  uint32_t c[gpu::kLdmCounterCount];
  std::memcpy(c, bytes.data(), sizeof c);
  return {c[gpu::kLdmCounterAllocated],    c[gpu::kLdmCounterOverflow], c[gpu::kLdmCounterUnfinished],
          c[gpu::kLdmCounterCasRetries],   c[gpu::kLdmCounterFp64],     c[gpu::kLdmCounterChunks],
          c[gpu::kLdmCounterChunkOverflow]};
}

std::vector<gpu::LdmMap> ldmMaps(const Scene& scene, const std::vector<glm::dvec3>& dirs, uint32_t resolution) {
  glm::vec3 lo, hi;
  scene.bounds(lo, hi);
  const glm::dvec3 centre = 0.5 * (glm::dvec3(lo) + glm::dvec3(hi));
  const double radius = std::max(0.5 * glm::length(glm::dvec3(hi) - glm::dvec3(lo)), 1e-6) * (1.0 + 1e-6);
  std::vector<gpu::LdmMap> maps;
  for (const glm::dvec3& d : dirs) {
    const LdmView v = ldmView(d, centre, radius, resolution);
    maps.push_back({glm::vec4(glm::vec3(v.dir), 0.0f), glm::vec4(glm::vec3(v.right), 0.0f),
                    glm::vec4(glm::vec3(v.up), 0.0f), glm::vec4(glm::vec3(v.centre), float(v.radius))});
  }
  return maps;
}

static std::atomic<uint64_t> gLdmSetBuilds{0};

uint64_t ldmSetBuildCount() { return gLdmSetBuilds.load(); }

std::unique_ptr<LdmBuild> makeSizedLdmBuild(const VulkanContext& ctx, const GpuScene& gpuScene, const Scene& scene,
                                            const std::vector<glm::dvec3>& dirs, uint32_t resolution,
                                            LdmBuildMethod method, LdmList kind, const char* effect) {
  ++gLdmSetBuilds;
  std::vector<gpu::LdmMap> maps = ldmMaps(scene, dirs, resolution);
  uint64_t fragments = 0, chunks = 0;
  {
    // A chunk list of one entry: every large pair is rasterized by its own thread, and counted.
    LdmBuild counting(ctx, gpuScene, scene, maps, resolution, 1, method, kind, {.chunkCapacity = 1});
    ctx.submitAndWait([&](VkCommandBuffer cmd) { counting.record(cmd); }, "sizing the layered depth maps");
    const LdmCounters c = counting.readCounters();
    fragments = c.allocated;
    chunks = c.chunks;
  }
  const uint64_t capacity = std::max<uint64_t>(1, fragments + fragments / 20);
  if (capacity > 0xFFFFFFF0ull)
    throw InputError(std::string("effects.") + effect + ": " + std::to_string(fragments) +
                     " LDM fragments do not fit 32-bit node ids; lower directions or ldm_resolution");
  const uint64_t chunkCapacity = std::min<uint64_t>(chunks + chunks / 20 + 64, 0xFFFFFFF0ull);
  return std::make_unique<LdmBuild>(ctx, gpuScene, scene, std::move(maps), resolution, uint32_t(capacity), method, kind,
                                    LdmBuildTuning{.chunkCapacity = uint32_t(chunkCapacity)});
}

}  // namespace hb
