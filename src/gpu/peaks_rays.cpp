// The device's ray rates (gpu/peaks.h): the same rays through every backend the device has, the
// built-in sets (addRayPeaks), the public tracers' three (addPublicRayPeaks) and ray files
// (traceRayFile). Split from peaks.cpp, whose microbenchmarks share its timing (peaks_detail.h).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "base/errors.h"
#include "base/text_format.h"
#include "gpu/accel.h"
#include "gpu/descriptor_binder.h"
#include "gpu/gpu_scene.h"
#include "gpu/peaks.h"
#include "gpu/peaks_detail.h"
#include "gpu/rt_pipeline.h"
#include "gpu/sync.h"
#include "gpu/trace_bvh.h"
#include "gpu/trace_work.h"
#include "gpu/vk_pipeline.h"
#include "gpu/vk_resources.h"
#include "gpu/warm_up.h"
#include "reference/ray_sets.h"

namespace hb {

using namespace peaks_detail;

namespace {

// The uniform block of peaks_rays.glsl.inc.
struct RayParams {
  glm::vec4 eye, forward, right, up, lo, hi;
  glm::uvec4 file;
};

// One ray set: a MODE of peaks_rays.glsl.inc, its figure's key and unit, and what it is in words.
struct RaySet {
  uint32_t mode;
  std::string key, unit, what;
  // A set with rays of its own (MODE 4, 5): its file and its uniforms (the file's count), and how
  // many rays; else the call's.
  const Buffer* file = nullptr;
  const Buffer* uniforms = nullptr;
  uint64_t rays = 0;
};

// Each set through each backend the device has (everyBackend false: the driver's only), the sets of
// a backend in order, one Peak each ("<key>_<backend>", the pipeline's without a suffix), the first
// once more at the end to catch a device whose speed changed. `rays` of the width x height launch are
// traced (a ray file's count; the grid's for the built-in sets). With `hits`, each backend's t per ray
// of the last set (Hits: -1 missed; none from the pipeline, which runs no hit shader) and its missed
// flags.
struct BackendHits {
  std::vector<float> t;
  std::vector<uint32_t> missed;
  std::vector<uint32_t> ids;  // ours and ray query: the triangle's draw-order id, ~0u missed
};
std::vector<Peak> measureRaySets(const VulkanContext& ctx, const Scene& scene, const RayParams& params, uint32_t width,
                                 uint32_t height, uint64_t callRays, const Buffer* fileRays,
                                 const std::vector<RaySet>& sets, const std::string& where, bool everyBackend,
                                 std::vector<std::string>& warnings, std::map<std::string, BackendHits>* hits) {
  const Sizes sizes = sizesFor(ctx.info());
  const bool cpu = ctx.info().type == "cpu";
  GpuScene gpuScene(ctx, scene);
  AccelerationStructures accel(ctx, gpuScene);
  // Ours at every width (bvh_width 2, 4, 8), and at widths 4 and 8 with persistent threads.
  struct Ours {
    uint32_t width;
    bool persistent;
  };
  std::vector<TraceBvh> bvhs;  // widths 2, 4, 8
  if (everyBackend)
    for (uint32_t w : {2u, 4u, 8u}) bvhs.push_back(buildTraceBvh(ctx, scene, w));
  auto bvhOf = [&](uint32_t w) -> const TraceBvh& { return bvhs[w == 2 ? 0 : w == 4 ? 1 : 2]; };
  const Buffer uniforms =
      uploadBuffer(ctx, &params, sizeof params, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, MemClass::Other);
  const size_t launched = size_t(width) * height;
  Buffer missed(
      ctx, launched * 4,
      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, false);
  Buffer hitT(ctx, launched * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT, false);
  Buffer hitIds(ctx, launched * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT, false);
  Buffer nextRay(ctx, 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, false);
  Buffer noFile(ctx, 32, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false);  // the built-in sets read no file
  // Ray query names its triangle by instance, geometry and primitive: IdBase maps them to draw order.
  const std::vector<uint32_t> idBaseData = triangleIdBase(scene);
  const Buffer idBase = uploadBuffer(ctx, idBaseData.data(), idBaseData.size() * sizeof(uint32_t),
                                     VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemClass::Other);
  // A backend: the driver's pipeline or ray query, or ours (`ours` set) in compute.
  struct Backend {
    std::string name;  // results' "backend": pipeline, rayquery, compute, compute-w4, compute-w8, compute-w4-persistent
    std::string through;
    bool pipeline = false;
    std::optional<Ours> ours;
  };
  // Per backend its resources: the driver's TLAS or our BVH.
  auto makeBinder = [&](const Backend& b, const RaySet* set = nullptr) {
    auto binder = std::make_unique<DescriptorBinder>("peaks.rays_" + b.name);
    binder->provide("Dst", missed);
    binder->provide("Hits", hitT);
    binder->provide("RayFile", set && set->file ? *set->file : fileRays ? *fileRays : noFile);
    // peaks_rays.glsl.inc's uniform block, named p
    binder->provide("p", set && set->uniforms ? *set->uniforms : uniforms);
    if (b.ours) {
      const TraceBvh& bvh = bvhOf(b.ours->width);
      binder->provide("BvhNodes", bvh.nodes);
      binder->provide("BvhTriangles", bvh.triangles);
      binder->provide("NextRay", nextRay);
      binder->provide("HitIds", hitIds);
    } else {
      binder->provide("tlas", accel.tlas());
      if (!b.pipeline) {  // ray query
        binder->provide("HitIds", hitIds);
        binder->provide("IdBase", idBase);
      }
    }
    return binder;
  };
  // Ours first: its camera rays write the surfaces the AO rays of every backend start from.
  std::vector<Backend> backends;
  if (everyBackend) {
    backends.push_back({"compute", "our binary BVH in compute (backend=compute, bvh_width=2)", false, Ours{2, false}});
    backends.push_back(
        {"compute-w4", "our 4-wide BVH in compute (backend=compute, bvh_width=4)", false, Ours{4, false}});
    backends.push_back(
        {"compute-w8", "our 8-wide BVH in compute (backend=compute, bvh_width=8)", false, Ours{8, false}});
    if (ctx.info().computeSubgroupBallot)
      for (uint32_t w : {4u, 8u})
        backends.push_back({"compute-w" + std::to_string(w) + "-persistent",
                            "our " + std::to_string(w) +
                                "-wide BVH in compute with persistent threads (each subgroup takes the next rays from "
                                "a global counter; not a renderer option)",
                            false, Ours{w, true}});
  }
  if (ctx.info().rayTracingPipeline) backends.push_back({"pipeline", "the driver's ray-tracing pipeline", true, {}});
  if (ctx.info().rayQuery && everyBackend) backends.push_back({"rayquery", "the driver's ray query", false, {}});
  // Persistent threads: enough groups of 64 to fill a large GPU (H200: 132 SMs, at most 32 groups of
  // 64 threads each), fewer where the rays are fewer.
  const uint32_t tiles = ((width + 7) / 8) * ((height + 7) / 8), persistentGroups = std::min(tiles, 4096u);
  // The device warmed again right before each timing: it idles while the CPU builds BVHs and makes
  // ray sets, and drops its clocks within a second (gpu/warm_up.h).
  DeviceWarmer warmer(ctx);
  auto measure = [&](const Backend& b, const DescriptorBinder& binder, const RaySet& set) {
    const uint64_t rays = set.rays ? set.rays : callRays;
    std::string suffix = "_" + b.name;
    std::replace(suffix.begin(), suffix.end(), '-', '_');
    std::unique_ptr<RaygenMissPipeline> rt;
    Pipeline compute(ctx);
    if (b.pipeline) {
      rt = std::make_unique<RaygenMissPipeline>(ctx, binder, "peaks_rays.rgen", "shadows.rmiss",
                                                SpecConstants{{set.mode}});
    } else {
      if (b.ours) {  // 8x8 threads a group
        const TraceBvh& bvh = bvhOf(b.ours->width);
        compute.createCompute(binder, "peaks_rays_compute.comp", 2 * sizeof(uint32_t),
                              {{set.mode, bvh.stack, traceStackShared(bvh, 64, true) ? 1u : 0u, bvh.width,
                                b.ours->persistent ? 1u : 0u}});
      } else
        compute.createCompute(binder, "peaks_rays_rayquery.comp", 2 * sizeof(uint32_t), {{set.mode}});
    }
    // Every ray writes 0 or 1: a ray left at 0xFFFFFFFF was not traced.
    ctx.submitAndWait([&](VkCommandBuffer cmd) { vkCmdFillBuffer(cmd, missed.handle(), 0, VK_WHOLE_SIZE, ~0u); },
                      "clearing the ray peaks' results");
    const bool persistent = b.ours && b.ours->persistent;
    VkDescriptorSet descriptors = (rt ? rt->pipeline() : compute).set();
    const uint32_t size[2] = {width, height};
    warmer.warm(kRewarmPolicy);
    Peak peak = makePeak(
        b.pipeline ? set.key : set.key + suffix, set.unit, double(rays),
        timeRepetitions(ctx, sizes,
                        [&](VkCommandBuffer cmd) {
                          if (persistent) {  // the counter back to the first ray, inside the timing
                            Sync sync;
                            sync.use(cmd, {{nextRay, access::kFill}});
                            vkCmdFillBuffer(cmd, nextRay.handle(), 0, 4, 0);
                            sync.use(cmd, {{nextRay, access::kComputeWrite}});
                          }
                          const Pipeline& pl = rt ? rt->pipeline() : compute;
                          vkCmdBindPipeline(cmd, pl.bindPoint(), pl.handle());
                          vkCmdBindDescriptorSets(cmd, pl.bindPoint(), pl.layout(), 0, 1, &descriptors, 0, nullptr);
                          if (rt) {
                            rt->traceRays(cmd, width, height);
                          } else {
                            vkCmdPushConstants(cmd, pl.layout(), VK_SHADER_STAGE_ALL, 0, sizeof size, size);
                            if (persistent)
                              vkCmdDispatch(cmd, persistentGroups, 1, 1);
                            else
                              vkCmdDispatch(cmd, (width + 7) / 8, (height + 7) / 8, 1);
                          }
                        }),
        set.what + where + ", through " + b.through);
    peak.backend = b.name;
    if (!b.pipeline) peak.compiled = pipelineStatistics(ctx, compute.handle());
    const std::vector<uint8_t> bytes = readbackBuffer(ctx, missed);
    const uint32_t* m = reinterpret_cast<const uint32_t*>(bytes.data());
    peak.missed = 0;
    for (size_t i = 0; i < rays; ++i) {
      if (m[i] > 1)
        throw DeviceError("the ray peak " + peak.key + " left ray " + std::to_string(i) +
                          " untraced: a bug in its shader or the driver");
      peak.missed += m[i];
    }
    if (hits && &set == &sets.back()) {
      BackendHits& h = (*hits)[b.name];
      h.missed.assign(m, m + rays);
      if (!b.pipeline) {
        const std::vector<uint8_t> tBytes = readbackBuffer(ctx, hitT);
        h.t.assign(reinterpret_cast<const float*>(tBytes.data()), reinterpret_cast<const float*>(tBytes.data()) + rays);
      }
      if (!b.pipeline && set.mode == 4u) {  // ours and ray query name the triangle
        const std::vector<uint8_t> idBytes = readbackBuffer(ctx, hitIds);
        const uint32_t* ids = reinterpret_cast<const uint32_t*>(idBytes.data());
        h.ids.assign(ids, ids + rays);
      }
    }
    return peak;
  };
  std::vector<Peak> out;
  for (const Backend& b : backends) {
    const std::unique_ptr<DescriptorBinder> binder = makeBinder(b);
    bool shared = false;
    for (const RaySet& set : sets) {
      if (set.file) {  // its own rays: its own bindings
        const std::unique_ptr<DescriptorBinder> own = makeBinder(b, &set);
        out.push_back(measure(b, *own, set));
        own->checkEveryNameRead();
      } else {
        out.push_back(measure(b, *binder, set));
        shared = true;
      }
    }
    if (shared) binder->checkEveryNameRead();
  }
  // The first figure once more, last: a device whose clocks or load changed while the figures ran
  // (the H200's first `peaks` on a cold machine once measured the driver's rays at 40 % of a second
  // run's, while its figures before that point agreed) makes the figures disagree with each other.
  // Beyond 5 % (run-to-run noise on the H200 is under 1 %), a warning says so.
  // An untimed first set (addPublicRayPeaks' warm-up, slow by design) is not the one compared.
  const size_t check = sets.size() > 1 && sets.front().unit == "rays_public_warmup" ? 1 : 0;
  if (!cpu && !backends.empty()) {
    const Peak again = measure(backends.front(), *makeBinder(backends.front(), &sets[check]), sets[check]);
    const Peak& first = out[check];
    const double ratio = again.perSecond / first.perSecond;
    if (std::abs(ratio - 1.0) > 0.05)
      warnings.push_back("ray peaks: " + first.key + " measured " + format("%.3g", first.perSecond) +
                         " rays/s first and " + format("%.3g", again.perSecond) + " last (" +
                         format("%+.0f", 100.0 * (ratio - 1.0)) +
                         " %): the device's speed changed while they ran (clocks, power or another "
                         "process); measure again (hybridbench peaks)");
  }
  return out;
}

}  // namespace

void addRayPeaks(const VulkanContext& ctx, const Scene& scene, Peaks& peaks, bool everyBackend) {
  if (!ctx.canTrace() || scene.cameras.empty()) return;
  const bool cpu = ctx.info().type == "cpu";
  const uint32_t width = cpu ? 160 : 1920, height = cpu ? 90 : 1080;
  RayParams params{};
  const Camera& camera = scene.cameras.front();
  const glm::mat4 toWorld = glm::inverse(camera.view);
  glm::vec3 lo, hi;
  scene.bounds(lo, hi);
  const float tanY = std::tan(0.5f * camera.yfov), aspect = float(width) / float(height);
  params.eye = toWorld[3];
  params.forward = glm::vec4(-glm::vec3(toWorld[2]), glm::length(hi - lo));  // w: tMax, the bounds' diagonal
  params.right = glm::vec4(glm::vec3(toWorld[0]) * tanY * aspect, 0);
  params.up = glm::vec4(glm::vec3(toWorld[1]) * tanY, 0);
  params.lo = glm::vec4(lo, 0);
  params.hi = glm::vec4(hi, 0);
  std::vector<RaySet> sets = {
      {0, "rays_camera", "rays_coherent", "camera rays through every pixel, closest hit"},
      {1, "rays_random_closest", "rays_random",
       "rays from random points of the scene's bounds in random directions, closest hit"},
      {2, "rays_random_occlusion", "rays_occlusion", "the same random rays as occlusion rays (first hit ends them)"},
      {3, "rays_ao", "rays_ao",
       "AO rays: from where each camera ray meets a surface, a random direction of the hemisphere facing the camera, "
       "occlusion rays as long as the bounds' diagonal"}};
  // The AO rays start where our BVH's camera rays met the scene: only where it ran.
  if (!everyBackend) sets.pop_back();
  const std::string where = " on " + scene.name + "'s scene (" + std::to_string(width) + "x" + std::to_string(height) +
                            " rays, no hit shader)";
  std::vector<Peak> figures = measureRaySets(ctx, scene, params, width, height, uint64_t(width) * height, nullptr, sets,
                                             where, everyBackend, peaks.warnings, nullptr);
  peaks.figures.insert(peaks.figures.end(), figures.begin(), figures.end());
}

namespace {

// Rays laid out over a width x height launch for MODE 4 and 5 (the rays first, the rest unused).
Buffer uploadFileRays(const VulkanContext& ctx, const std::vector<RayRecord>& rays, uint32_t width, uint32_t height) {
  HB_ASSERT(uint64_t(width) * height >= rays.size());
  std::vector<float> words(size_t(width) * height * 8, 0.0f);
  if (!rays.empty()) std::memcpy(words.data(), rays.data(), rays.size() * sizeof(RayRecord));
  return uploadBuffer(ctx, words.data(), words.size() * sizeof(float), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                      MemClass::Other);
}

}  // namespace

void addPublicRayPeaks(const VulkanContext& ctx, const Scene& scene, Peaks& peaks) {
  if (!ctx.canTrace() || scene.cameras.empty()) return;
  const bool cpu = ctx.info().type == "cpu";
  const uint32_t width = cpu ? 160 : 1920, height = cpu ? 90 : 1080;  // addRayPeaks' size
  const RayView view = rayViewOf(scene.cameras.front(), width, height);
  const std::vector<RayRecord> camera = cameraRays(view);
  const Bvh bvh = buildBvh(scene);
  const RayHits hits = traceOnCpu(bvh, camera);
  const SecondaryParams secondary;  // rays export's defaults: 1 mm off, AO of 1 m, the light at (0, 6, 0)
  const std::pair<const char*, std::vector<RayRecord>> sets[] = {{"camera", camera},
                                                                 {"ao", aoRays(bvh, camera, hits, secondary)},
                                                                 {"shadow", shadowRays(bvh, camera, hits, secondary)}};
  // One call for the three, after one untimed pass: the sets are made on the CPU first, for seconds
  // in which the GPU idles and lowers its clocks, and a call of its own for each set would idle it
  // again while its BVHs are built (on the H200 the public figures then ran at a third of raybench's,
  // recovering only slowly, and peaks' own check warned of it).
  std::vector<Buffer> files, uniforms;
  std::vector<RaySet> measured;
  files.reserve(4);
  uniforms.reserve(4);
  for (size_t k = 0; k < 4; ++k) {
    const auto& [kind, rays] = sets[k == 0 ? 0 : k - 1];  // the camera set twice: the first untimed
    if (rays.empty()) continue;
    RayParams params{};
    params.file = glm::uvec4(uint32_t(rays.size()), 0, 0, 0);
    files.push_back(uploadFileRays(ctx, rays, width, height));
    uniforms.push_back(uploadBuffer(ctx, &params, sizeof params, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, MemClass::Other));
    const std::string key = k == 0 ? "rays_public_warmup" : std::string("rays_public_") + kind;
    measured.push_back({4u, key, key,
                        std::to_string(rays.size()) + " " + kind +
                            " rays of the public tracers' figures (rays export's, from the first camera), closest hit",
                        &files.back(), &uniforms.back(), rays.size()});
  }
  if (measured.empty()) return;
  const std::string where =
      " on " + scene.name + "'s scene (" + std::to_string(width) + "x" + std::to_string(height) + ", no hit shader)";
  const std::vector<Peak> figures = measureRaySets(ctx, scene, RayParams{}, width, height, 0, nullptr, measured, where,
                                                   true, peaks.warnings, nullptr);
  for (const Peak& p : figures)
    if (p.unit != "rays_public_warmup") peaks.figures.push_back(p);
}

namespace {

// raybench's loads ceiling (shaders/peaks/peaks_rays_loads.comp.glsl): the fetches of our traversal
// at `bvhWidth` for the file's rays, replayed on the CPU (gpu/trace_work.h) and laid out a subgroup
// chunk of 32 invocations at a time, then loaded on the GPU in that order, each address waiting for
// the loads before it, with no test. Its rate bounds the traversal's from above: what the memory
// allows these addresses. The figure's backend is "compute-w<W>-loads"; its missed flags are the
// replay's.
// half: each group of 4 children read as 4 vec4 of a 64 B stride instead of 7 of 128 B (a node
// compressed to half its bytes; backend "compute-w<W>-loads-half").
// None (and a warning) where the replay's fetches do not fit one storage buffer of the device.
std::optional<Peak> measureLoadsCeiling(const VulkanContext& ctx, const Scene& scene, const RayFile& file,
                                        uint32_t width, uint32_t height, uint32_t bvhWidth, bool half,
                                        const std::string& where, RayFileHits& hits,
                                        std::vector<std::string>& warnings) {
  const TraceBvhLayout layout = layoutTraceBvh(scene.worldTriangles(), bvhWidth);
  std::vector<std::vector<uint32_t>> events;
  std::vector<uint8_t> replayMissed;
  traceWork(layout, file.rays, file.info.query == "any", &events, &replayMissed);
  const uint32_t tilesX = (width + 7) / 8, tilesY = (height + 7) / 8;
  const size_t rays = file.rays.size();
  std::vector<uint32_t> chunkBase(size_t(tilesX) * tilesY * 2, 0), rayInfo(rays, 0);
  // The ray of invocation li (0..63) of tile (tx, ty), or ~0 for none (as peaks_rays.glsl.inc).
  auto rayOf = [&](uint32_t tx, uint32_t ty, uint32_t li) -> size_t {
    const uint32_t x = tx * 8 + li % 8, y = ty * 8 + li / 8;
    if (x >= width || y >= height) return ~size_t(0);
    const size_t i = size_t(y) * width + x;
    return i < rays ? i : ~size_t(0);
  };
  VkPhysicalDeviceProperties props;
  vkGetPhysicalDeviceProperties(ctx.physical(), &props);
  const uint64_t maxEntries = props.limits.maxStorageBufferRange / 4;  // one binding holds the events
  uint64_t total = 0;
  for (uint32_t ty = 0; ty < tilesY; ++ty)
    for (uint32_t tx = 0; tx < tilesX; ++tx)
      for (uint32_t chunk = 0; chunk < 2; ++chunk) {
        size_t steps = 0;
        for (uint32_t lane = 0; lane < 32; ++lane) {
          const size_t i = rayOf(tx, ty, 32 * chunk + lane);
          if (i != ~size_t(0)) steps = std::max(steps, events[i].size());
        }
        chunkBase[(size_t(ty) * tilesX + tx) * 2 + chunk] = uint32_t(total);
        total += 32 * uint64_t(steps);
        if (total > maxEntries) {
          warnings.push_back("raybench: no loads ceiling: the replay of " + std::to_string(rays) +
                             " rays holds more than " + std::to_string(maxEntries) +
                             " fetches (the device's largest storage buffer); trace fewer rays a file for one");
          return std::nullopt;
        }
      }
  std::vector<uint32_t> flat(std::max<uint64_t>(total, 1), 0);
  for (uint32_t ty = 0; ty < tilesY; ++ty)
    for (uint32_t tx = 0; tx < tilesX; ++tx)
      for (uint32_t li = 0; li < 64; ++li) {
        const size_t i = rayOf(tx, ty, li);
        if (i == ~size_t(0)) continue;
        const uint64_t base = chunkBase[(size_t(ty) * tilesX + tx) * 2 + li / 32];
        for (size_t k = 0; k < events[i].size(); ++k) flat[base + 32 * k + li % 32] = events[i][k];
        rayInfo[i] = uint32_t(events[i].size()) | (replayMissed[i] ? 0x80000000u : 0u);
      }
  events.clear();
  events.shrink_to_fit();
  const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  const Buffer nodes =
      uploadBuffer(ctx, layout.wide.data(), layout.wide.size() * sizeof(glm::vec4), storage, MemClass::Other);
  const Buffer triangles =
      uploadBuffer(ctx, layout.triangles.data(), layout.triangles.size() * sizeof(glm::vec4), storage, MemClass::Other);
  const Buffer eventBuf = uploadBuffer(ctx, flat.data(), flat.size() * 4, storage, MemClass::Other);
  const Buffer chunkBuf = uploadBuffer(ctx, chunkBase.data(), chunkBase.size() * 4, storage, MemClass::Other);
  const Buffer infoBuf = uploadBuffer(ctx, rayInfo.data(), rayInfo.size() * 4, storage, MemClass::Other);
  Buffer missed(ctx, size_t(width) * height * 4,
                storage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, false);
  DescriptorBinder binder("peaks.rays_loads");
  binder.provide("Dst", missed);
  binder.provide("BvhNodes", nodes);
  binder.provide("BvhTriangles", triangles);
  binder.provide("Events", eventBuf);
  binder.provide("ChunkBase", chunkBuf);
  binder.provide("RayInfo", infoBuf);
  Pipeline compute(ctx);
  compute.createCompute(binder, "peaks_rays_loads.comp", 4 * sizeof(uint32_t),
                        {{bvhWidth, half ? 4u : 7u, half ? 4u : kWideGroupVec4s}});
  binder.checkEveryNameRead();
  ctx.submitAndWait([&](VkCommandBuffer cmd) { vkCmdFillBuffer(cmd, missed.handle(), 0, VK_WHOLE_SIZE, ~0u); },
                    "clearing the loads ceiling's results");
  const uint32_t push[4] = {width, height, uint32_t(rays), 0u};
  VkDescriptorSet descriptors = compute.set();
  DeviceWarmer warmer(ctx);
  warmer.warm(kRewarmPolicy);
  const std::string backend = "compute-w" + std::to_string(bvhWidth) + "-loads" + (half ? "-half" : "");
  Peak peak = makePeak(
      "rays_file_compute_w" + std::to_string(bvhWidth) + "_loads" + (half ? "_half" : ""), "rays_file", double(rays),
      timeRepetitions(ctx, sizesFor(ctx.info()),
                      [&](VkCommandBuffer cmd) {
                        vkCmdBindPipeline(cmd, compute.bindPoint(), compute.handle());
                        vkCmdBindDescriptorSets(cmd, compute.bindPoint(), compute.layout(), 0, 1, &descriptors, 0,
                                                nullptr);
                        vkCmdPushConstants(cmd, compute.layout(), VK_SHADER_STAGE_ALL, 0, sizeof push, push);
                        vkCmdDispatch(cmd, tilesX, tilesY, 1);
                      }),
      std::to_string(rays) + " rays of a ray file (" + file.info.kind + "): the loads alone of our " +
          std::to_string(bvhWidth) + "-wide traversal (" + std::to_string(total / 32) +
          " subgroup steps), in its order, each waiting for the one before, with no test" +
          (half ? ", a node's group of 4 children read as 64 B (4 vec4) instead of 112 B" : "") + where +
          ": a ceiling, not a tracer");
  peak.backend = backend;
  peak.compiled = pipelineStatistics(ctx, compute.handle());
  const std::vector<uint8_t> bytes = readbackBuffer(ctx, missed);
  const uint32_t* m = reinterpret_cast<const uint32_t*>(bytes.data());
  peak.missed = 0;
  for (size_t i = 0; i < rays; ++i) {
    if (m[i] > 1)
      throw DeviceError("the loads ceiling left ray " + std::to_string(i) +
                        " unvisited: a bug in its shader or the driver");
    peak.missed += m[i];
  }
  hits.missed.assign(m, m + rays);
  return peak;
}

}  // namespace

RayFileTrace traceRayFile(const VulkanContext& ctx, const Scene& scene, const RayFile& file) {
  HB_ASSERT(ctx.canTrace() && !file.rays.empty());
  RayParams params{};
  params.file = glm::uvec4(uint32_t(file.rays.size()), 0, 0, 0);
  const uint32_t width = file.info.grid[0], height = file.info.grid[1];
  const Buffer rays = uploadFileRays(ctx, file.rays, width, height);
  const bool any = file.info.query == "any";
  const std::vector<RaySet> sets = {{any ? 5u : 4u, "rays_file", "rays_file",
                                     std::to_string(file.rays.size()) + " rays of a ray file (" + file.info.kind +
                                         "), " + (any ? "any hit" : "closest hit")}};
  const std::string where = " on " + scene.name + "'s scene (a " + std::to_string(width) + "x" +
                            std::to_string(height) + " launch, no hit shader)";
  RayFileTrace out;
  std::map<std::string, BackendHits> hits;
  out.figures = measureRaySets(ctx, scene, params, width, height, file.rays.size(), &rays, sets, where, true,
                               out.warnings, &hits);
  for (auto& [backend, h] : hits) out.hits[backend] = {std::move(h.t), std::move(h.missed), std::move(h.ids)};
  // The ceiling of the default width's traversal: its loads alone, as they are and at half the bytes.
  for (bool half : {false, true}) {
    RayFileHits loadsHits;
    const std::optional<Peak> ceiling =
        measureLoadsCeiling(ctx, scene, file, width, height, 4, half, where, loadsHits, out.warnings);
    if (!ceiling) break;
    out.figures.push_back(*ceiling);
    out.hits[ceiling->backend] = std::move(loadsHits);
  }
  return out;
}

}  // namespace hb
