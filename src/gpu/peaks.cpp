#include "gpu/peaks.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "base/errors.h"
#include "base/text_format.h"
#include "gpu/accel.h"
#include "gpu/descriptor_binder.h"
#include "gpu/gpu_scene.h"
#include "gpu/gpu_timer.h"
#include "gpu/raster_pipeline.h"
#include "gpu/rt_pipeline.h"
#include "gpu/sync.h"
#include "gpu/trace_bvh.h"
#include "gpu/vk_pipeline.h"
#include "gpu/vk_resources.h"
#include "reference/ray_sets.h"

namespace hb {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

// Bumped whenever a microbenchmark changes what it measures: cached figures of another version are
// measured again.
constexpr int kPeaksVersion = 2;

// What one repetition of each microbenchmark does, by device kind. A GPU's buffers are far larger
// than its last-level cache (H100: 50 MiB) so that bandwidth is DRAM's; a CPU device's are small
// enough to keep the whole measurement near a second on lavapipe.
struct Sizes {
  uint32_t bufferBytes;    // read, write, copy: each buffer
  uint32_t atomics;        // atomic operations a repetition
  uint32_t fmaThreads;     // FMA threads ...
  uint32_t fmaIterations;  // ... of 8 FMAs an iteration each
  uint32_t target;         // the raster target is target x target pixels
  uint32_t cells;          // triangle rate: cells x cells 1-pixel cells (two triangles each)
  uint32_t fillLayers;     // fill rate: screen-sized quads drawn this many times
  int warmup, repetitions;
};

Sizes sizesFor(const DeviceInfo& d) {
  if (d.type == "cpu") return {16u << 20, 1u << 20, 1u << 14, 256, 256, 128, 4, 1, 5};
  return {512u << 20, 1u << 26, 1u << 20, 4096, 4096, 2048, 32, 3, 15};
}

double median(std::vector<double> v) {
  HB_ASSERT(!v.empty());
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct PushConstants {
  uint32_t elements, iterations, sentinel, pad;
};

// Times `record` (one repetition's commands) warmup + repetitions times; each repetition is its own
// submission. On a GPU the timestamps around the commands, else the host clock around submitAndWait.
std::vector<double> timeRepetitions(const VulkanContext& ctx, const Sizes& sizes,
                                    const std::function<void(VkCommandBuffer)>& record) {
  const bool gpu = ctx.info().type != "cpu";
  GpuTimer timer(ctx, 1);
  std::vector<double> ms;
  for (int i = 0; i < sizes.warmup + sizes.repetitions; ++i) {
    const auto start = std::chrono::steady_clock::now();
    ctx.submitAndWait(
        [&](VkCommandBuffer cmd) {
          if (gpu && timer.available()) {
            timer.reset(cmd);
            timer.frameBegin(cmd);
            timer.begin(cmd, "peak");
          }
          record(cmd);
          if (gpu && timer.available()) {
            timer.end(cmd);
            timer.frameEnd(cmd);
          }
        },
        "a peaks microbenchmark");
    double t = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (gpu && timer.available()) {
      const auto passes = timer.read(nullptr);
      if (!passes.empty()) t = passes.front().second;
    }
    if (i >= sizes.warmup) ms.push_back(t);
  }
  return ms;
}

Peak makePeak(std::string key, std::string unit, double work, std::vector<double> ms, std::string description) {
  Peak p{std::move(key), std::move(unit), 0, work, std::move(ms), std::move(description)};
  const double m = median(p.ms);
  p.perSecond = m > 0 ? work / (m * 1e-3) : 0;
  return p;
}

void measureCompute(const VulkanContext& ctx, const Sizes& sizes, std::vector<Peak>& out) {
  const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  Buffer src(ctx, sizes.bufferBytes, usage, false), dst(ctx, sizes.bufferBytes, usage, false);
  DescriptorBinder binder("peaks");
  binder.provide("Src", src);
  binder.provide("Dst", dst);
  binder.provide("DstWords", dst);              // peaks.comp's word view of the same buffer
  ctx.submitAndWait([&](VkCommandBuffer cmd) {  // defined contents: the read sums something real
    vkCmdFillBuffer(cmd, src.handle(), 0, VK_WHOLE_SIZE, 0x01010101u);
    vkCmdFillBuffer(cmd, dst.handle(), 0, VK_WHOLE_SIZE, 0u);
  });
  const uint32_t maxGroups = ctx.properties().limits.maxComputeWorkGroupCount[0];
  // One compute pipeline of `shader` timed over repetitions of one dispatch of `groups` workgroups.
  auto timeDispatch = [&](const char* shader, const SpecConstants& spec, const PushConstants& pc, uint32_t groups) {
    Pipeline p(ctx);
    p.createCompute(binder, shader, sizeof(PushConstants), spec);
    return timeRepetitions(ctx, sizes, [&](VkCommandBuffer cmd) {
      // Each repetition waits for the writes before it (the fill, the last repetition), as a dispatch
      // of a frame would: the barrier is part of what is timed.
      Sync sync;
      const Access before{VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | access::kFill.stages,
                          VK_ACCESS_2_SHADER_WRITE_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT};
      sync.assume(src, before);
      sync.assume(dst, before);
      sync.use(cmd, {{src, access::kComputeWrite}, {dst, access::kComputeWrite}});
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.handle());
      VkDescriptorSet s = p.set();
      vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.layout(), 0, 1, &s, 0, nullptr);
      vkCmdPushConstants(cmd, p.layout(), VK_SHADER_STAGE_ALL, 0, sizeof pc, &pc);
      vkCmdDispatch(cmd, groups, 1, 1);
    });
  };
  // Enough workgroups to fill any GPU several times over; the grid-stride loops cover the rest.
  auto groupsFor = [&](uint32_t threads) { return std::min({(threads + 255u) / 256u, maxGroups, 65535u}); };
  auto run = [&](uint32_t mode, uint32_t elements, uint32_t threads, uint32_t iterations) {
    return timeDispatch("peaks.comp", {{mode}}, {elements, iterations, 0xFFFFFFFFu, 0}, groupsFor(threads));
  };
  // The floor under any timed dispatch: one workgroup that does nothing, between two timestamps.
  out.push_back(makePeak("dispatch_empty", "dispatches", 1.0, timeDispatch("peaks.comp", {{1u}}, {0, 0, 0, 0}, 1),
                         "one workgroup that writes nothing: the floor under any timed dispatch"));
  const uint32_t vec4s = sizes.bufferBytes / 16u;
  const double bytes = double(sizes.bufferBytes);
  out.push_back(
      makePeak("memory_read", "bytes", bytes, run(0, vec4s, vec4s, 0), "read a buffer once (uvec4 loads, summed)"));
  out.push_back(
      makePeak("memory_write", "bytes", bytes, run(1, vec4s, vec4s, 0), "write a buffer once (uvec4 stores)"));
  out.push_back(makePeak("memory_copy", "bytes", 2 * bytes, run(2, vec4s, vec4s, 0),
                         "copy a buffer into another (bytes read + bytes written)"));
  const uint32_t atomics = std::min(sizes.atomics, sizes.bufferBytes / 4u);
  out.push_back(makePeak("atomic_add_distinct", "atomics", atomics, run(3, atomics, atomics, 0),
                         "32-bit atomicAdd, each thread to its own word (coalesced)"));
  out.push_back(makePeak("atomic_add_contended", "atomics_contended", atomics, run(4, atomics, atomics, 0),
                         "32-bit atomicAdd, the 256 threads of a workgroup to one word"));
  out.push_back(makePeak("fma_fp32", "fma", double(sizes.fmaThreads) * sizes.fmaIterations * 8.0,
                         run(5, sizes.fmaThreads, sizes.fmaThreads, sizes.fmaIterations),
                         "fp32 fma, 8 independent chains a thread (one fma = 2 flops)"));
  if (ctx.info().bufferInt64Atomics) {
    const uint32_t keys = std::min(sizes.atomics, sizes.bufferBytes / 8u);
    out.push_back(makePeak("atomic_min_u64", "atomics64", keys,
                           timeDispatch("peaks_atomic64.comp", {}, {keys, 0, 0x9E3779B9u, 0}, groupsFor(keys)),
                           "64-bit atomicMin, each thread to its own word (the visibility buffer's operation)"));
  }
  binder.checkEveryNameRead();
}

void measureRaster(const VulkanContext& ctx, const Sizes& sizes, std::vector<Peak>& out) {
  Pipeline pipeline(ctx);
  pipeline.createLayout({}, 16);
  ShaderModule vert(ctx, "peaks_raster.vert");
  RasterPipelineDesc desc;
  desc.layout = pipeline.layout();
  desc.vertex = vert.handle();
  desc.vertexAttributes = 0;
  desc.depthWrite = true;
  desc.depthCompare = VK_COMPARE_OP_ALWAYS;  // every fragment writes: the rate, not the early-out
  pipeline.pipeline_ = createRasterPipeline(ctx, desc);
  pipeline.bindPoint_ = VK_PIPELINE_BIND_POINT_GRAPHICS;
  const uint32_t size = sizes.target;
  Image depth(ctx, size, size, VK_FORMAT_D32_SFLOAT, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
              VK_IMAGE_ASPECT_DEPTH_BIT);
  ctx.submitAndWait([&](VkCommandBuffer cmd) {
    Sync sync;
    sync.use(cmd, {{depth, access::kDepthAttachment.discarding()}});
  });
  // The grid's index buffer: cells x cells cells of two triangles over (cells + 1)² vertices.
  auto gridIndices = [&](uint32_t cells) {
    std::vector<uint32_t> idx;
    idx.reserve(size_t(cells) * cells * 6);
    for (uint32_t y = 0; y < cells; ++y)
      for (uint32_t x = 0; x < cells; ++x) {
        const uint32_t a = y * (cells + 1) + x, b = a + 1, c = a + cells + 1, d = c + 1;
        idx.insert(idx.end(), {a, b, c, b, d, c});
      }
    return uploadBuffer(ctx, idx.data(), idx.size() * 4, VK_BUFFER_USAGE_INDEX_BUFFER_BIT, MemClass::Other);
  };
  auto draw = [&](uint32_t cells, uint32_t instances) {
    const uint32_t push[4] = {cells, cells, 0, 0};
    const Buffer indices = gridIndices(cells);
    return timeRepetitions(ctx, sizes, [&](VkCommandBuffer cmd) {
      // The last repetition's depth writes before this one's clear, inside the timing.
      Sync sync;
      sync.assume(depth, {VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT, VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT});
      sync.use(cmd, {{depth,
                      {VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT, VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                       VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL}}});
      VkRenderingAttachmentInfo da{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
      da.imageView = depth.view();
      da.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
      da.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
      da.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
      VkRenderingInfo ri{VK_STRUCTURE_TYPE_RENDERING_INFO};
      ri.renderArea = {{0, 0}, {size, size}};
      ri.layerCount = 1;
      ri.pDepthAttachment = &da;
      vkCmdBeginRendering(cmd, &ri);
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.handle());
      VkViewport viewport{0, 0, float(size), float(size), 0.0f, 1.0f};
      VkRect2D scissor{{0, 0}, {size, size}};
      vkCmdSetViewport(cmd, 0, 1, &viewport);
      vkCmdSetScissor(cmd, 0, 1, &scissor);
      vkCmdPushConstants(cmd, pipeline.layout(), VK_SHADER_STAGE_ALL, 0, sizeof push, push);
      vkCmdBindIndexBuffer(cmd, indices.handle(), 0, VK_INDEX_TYPE_UINT32);
      vkCmdDrawIndexed(cmd, 6 * cells * cells, instances, 0, 0, 0);
      vkCmdEndRendering(cmd);
    });
  };
  // Pixel-sized triangles: cells of (target / cells)² pixels, split in two.
  const double triangles = 2.0 * sizes.cells * sizes.cells;
  const uint32_t cellPixels = size / sizes.cells;
  out.push_back(makePeak("raster_triangles", "triangles", triangles, draw(sizes.cells, 1),
                         "depth-only triangles of " + format("%g", cellPixels * cellPixels / 2.0) +
                             " pixels each (cells of " + std::to_string(cellPixels) + "x" + std::to_string(cellPixels) +
                             " split in two), an indexed grid, no vertex input"));
  out.push_back(makePeak("raster_fill", "fragments", double(size) * size * sizes.fillLayers, draw(1, sizes.fillLayers),
                         "depth-only fragments: two screen-sized triangles drawn " + std::to_string(sizes.fillLayers) +
                             " times over " + std::to_string(size) + "x" + std::to_string(size)));
}

}  // namespace

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
  std::vector<uint32_t> ids;  // ours: the triangle's draw-order id, ~0u missed
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
      if (b.ours && set.mode == 4u) {
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
  return out;
}

double Peaks::rateFor(const std::string& unit, const std::string& backend) const {
  if (!backend.empty())
    for (const Peak& p : figures)
      if (p.unit == unit && p.backend == backend) return p.perSecond;
  if (unit == "bytes") {
    double best = 0;
    for (const Peak& p : figures)
      if (p.unit == "bytes") best = std::max(best, p.perSecond);
    return best;
  }
  for (const Peak& p : figures)
    if (p.unit == unit) return p.perSecond;
  return 0;
}

Peaks measurePeaks(const VulkanContext& ctx) {
  const Sizes sizes = sizesFor(ctx.info());
  Peaks peaks;
  const GpuTimer probe(ctx, 1);
  peaks.timing = ctx.info().type == "cpu" ? "host clock around each submission (CPU device)"
                 : !probe.available()     ? "host clock around each submission (the device has no timestamps)"
                                          : "GPU timestamps around each repetition";
  measureCompute(ctx, sizes, peaks.figures);
  measureRaster(ctx, sizes, peaks.figures);
  return peaks;
}

json toJson(const Peaks& peaks, const DeviceInfo& device) {
  json figures = json::object();
  for (const Peak& p : peaks.figures) {
    std::vector<double> sorted = p.ms;
    std::sort(sorted.begin(), sorted.end());
    figures[p.key] = {
        {"unit", p.unit},
        {"per_s", p.perSecond},
        {"work", p.work},
        {"ms", {{"median", median(p.ms)}, {"min", sorted.front()}, {"max", sorted.back()}, {"samples", p.ms}}},
        {"description", p.description}};
    if (!p.backend.empty()) figures[p.key]["backend"] = p.backend;
    if (p.missed >= 0) figures[p.key]["missed"] = p.missed;
  }
  json j = {{"version", kPeaksVersion}, {"device", device.name},
            {"uuid", device.uuid},      {"driver", device.driverName + " " + device.driverVersion},
            {"timing", peaks.timing},   {"figures", figures}};
  if (!peaks.warnings.empty()) j["warnings"] = peaks.warnings;
  return j;
}

Peaks peaksFromJson(const json& j) {
  Peaks peaks;
  peaks.timing = j.value("timing", "");
  peaks.warnings = j.value("warnings", std::vector<std::string>{});
  // A named copy: items() refers to its json, and a temporary's would end before the loop body
  // (C++20 extends the life of the range's outermost temporary only).
  const json figures = j.value("figures", json::object());
  for (const auto& [key, f] : figures.items()) {
    Peak p;
    p.key = key;
    p.unit = f.value("unit", "");
    p.perSecond = f.value("per_s", 0.0);
    p.work = f.value("work", 0.0);
    if (f.contains("ms")) p.ms = f["ms"].value("samples", std::vector<double>{});
    p.description = f.value("description", "");
    p.backend = f.value("backend", "");
    p.missed = f.value("missed", -1.0);
    peaks.figures.push_back(p);
  }
  return peaks;
}

std::string formatRate(double perSecond, const std::string& unit) {
  const char* prefixes[] = {"", "k", "M", "G", "T", "P"};
  int i = 0;
  double v = perSecond;
  while (std::abs(v) >= 1000.0 && i < 5) {
    v /= 1000.0;
    ++i;
  }
  if (unit == "bytes") return format("%.3g %sB/s", v, prefixes[i]);
  return format("%.3g %s%s%s/s", v, prefixes[i], i ? " " : "", unit.c_str());
}

std::string peaksCachePath(const DeviceInfo& device) {
  fs::path dir;
  if (const char* d = std::getenv("HYBRIDBENCH_PEAKS_CACHE"); d && *d)
    dir = d;
  else if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x)
    dir = fs::path(x) / "hybridbench" / "peaks";
  else if (const char* h = std::getenv("HOME"); h && *h)
    dir = fs::path(h) / ".cache" / "hybridbench" / "peaks";
  else
    return "";
  std::string key =
      device.uuid + "-" + device.driverVersion + "-" + device.driverInfo + "-v" + std::to_string(kPeaksVersion);
  for (char& c : key)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '.') c = '_';
  return (dir / (key + ".json")).string();
}

Peaks cachedPeaks(const VulkanContext& ctx, bool* fromCache) {
  const std::string path = peaksCachePath(ctx.info());
  if (!path.empty()) {
    std::ifstream in(path);
    if (in) {
      try {
        const json j = json::parse(in);
        if (j.value("version", 0) == kPeaksVersion && j.value("uuid", "") == ctx.info().uuid) {
          if (fromCache) *fromCache = true;
          return peaksFromJson(j);
        }
      } catch (const std::exception&) {  // a damaged cache entry is measured again
      }
    }
  }
  Peaks peaks = measurePeaks(ctx);
  if (fromCache) *fromCache = false;
  if (!path.empty()) {
    std::error_code ec;
    fs::create_directories(fs::path(path).parent_path(), ec);
    const std::string tmp = path + ".tmp";
    std::ofstream out(tmp);
    if (out) {
      out << toJson(peaks, ctx.info()).dump(2) << "\n";
      out.close();
      fs::rename(tmp, path, ec);
    }
  }
  return peaks;
}

}  // namespace hb
