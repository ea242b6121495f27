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
#include "gpu/peaks_detail.h"
#include "gpu/raster_pipeline.h"
#include "gpu/rt_pipeline.h"
#include "gpu/sync.h"
#include "gpu/trace_bvh.h"
#include "gpu/vk_pipeline.h"
#include "gpu/vk_resources.h"
#include "gpu/warm_up.h"

namespace hb {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

// Bumped whenever a microbenchmark changes what it measures: cached figures of another version are
// measured again.
constexpr int kPeaksVersion = 2;

}  // namespace

namespace peaks_detail {

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

}  // namespace peaks_detail

namespace {

using namespace peaks_detail;

struct PushConstants {
  uint32_t elements, iterations, sentinel, pad;
};

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
  const WarmUp warm = warmDevice(ctx);
  peaks.warmUp = toJson(warm);
  if (const std::string w = warmUpWarning(warm); !w.empty()) peaks.warnings.push_back(w);
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
  if (!peaks.warmUp.is_null()) j["warm_up"] = peaks.warmUp;
  return j;
}

Peaks peaksFromJson(const json& j) {
  Peaks peaks;
  peaks.timing = j.value("timing", "");
  peaks.warnings = j.value("warnings", std::vector<std::string>{});
  if (j.contains("warm_up")) peaks.warmUp = j["warm_up"];
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
