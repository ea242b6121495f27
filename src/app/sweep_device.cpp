#include "app/sweep_device.h"

#include <unistd.h>

#include <sys/utsname.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>

#include "analysis/render_outputs.h"
#include "app/scene_setup.h"
#include "app/sweep_results.h"
#include "base/errors.h"
#include "base/text_format.h"
#include "base/version.h"
#include "effects/shadows/shadows_part.h"
#include "frame/renderer.h"
#include "gpu/vk_resources.h"
#include "report/stats.h"
#include "report/tables.h"
#include "scene/gltf/gltf_io.h"
#include "shared/gpu_types.h"

namespace hb {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

json hostJson() {
  json h;
  char name[256] = {};
  gethostname(name, sizeof name - 1);
  h["hostname"] = name;
  struct utsname u {};
  if (uname(&u) == 0) h["os"] = std::string(u.sysname) + " " + u.release + " " + u.machine;
  std::ifstream cpu("/proc/cpuinfo");
  for (std::string line; std::getline(cpu, line);)
    if (line.rfind("model name", 0) == 0) {
      h["cpu"] = line.substr(line.find(':') + 2);
      break;
    }
  h["cores"] = sysconf(_SC_NPROCESSORS_ONLN);
  std::time_t now = std::time(nullptr);
  char date[64];
  std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  h["date"] = date;
  return h;
}

json deviceJson(const DeviceInfo& d, const std::string& backend) {
  return {{"name", d.name},
          {"vendor", d.vendor},
          {"vendor_id", d.vendorId},
          {"device_id", d.deviceId},
          {"uuid", d.uuid},
          {"type", d.type},
          {"driver", d.driverName + " " + d.driverVersion + " (" + d.driverInfo + ")"},
          {"api_version", d.apiVersion},
          {"rt_backend", backend},
          {"timestamp_period_ns", d.timestampPeriodNs},
          {"timestamp_valid_bits", d.timestampValidBits}};
}

volatile std::sig_atomic_t gInterrupted = 0;
void onSignal(int) { gInterrupted = 1; }

std::string joinNames(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

// The no-culling reference of each (scene, resolution, backend), rendered once (docs/methods/thesis.md
// "Accuracy"). None for scenes with more lights than one tile list holds: with culling off such a
// reference would itself drop lights.
class ReferenceCache {
 public:
  const ReferenceFrame* get(const VulkanContext& ctx, const Config& config, const VariantParams& params,
                            SceneCache& scenes) {
    const Scene& scene = scenes.get(config, params);
    const EffectsRequest effects = effectsRequestFor(config);
    if (scene.lights.size() > gpu::kMaxLightsPerTile || !planFrame(scene, effects).runs("shadows")) return nullptr;
    VariantParams rp = referenceParams(params);
    const std::string key = toJson(rp).dump();
    auto it = frames_.find(key);
    if (it == frames_.end()) {
      Renderer renderer(ctx, scene, renderSettingsFor(rp, effects));
      renderer.renderFrame(true);
      it = frames_.emplace(key, captureReference(renderer, scene)).first;
    }
    return &it->second;
  }

 private:
  std::map<std::string, ReferenceFrame> frames_;
};

// Runs one variant; returns its run record (status ok) or throws.
json runVariant(const VulkanContext& ctx, const Config& config, const Variant& v, SceneCache& scenes,
                ReferenceCache& references, const std::string& imageDir, bool images, uint32_t warmup,
                uint32_t measured) {
  const Scene& scene = scenes.get(config, v.params);
  const ReferenceFrame* reference = references.get(ctx, config, v.params, scenes);
  RenderSettings settings = renderSettingsFor(v.params, effectsRequestFor(config));
  Renderer renderer(ctx, scene, settings);
  std::map<std::string, uint64_t> memory = memoryByClass();

  // Warm-up: the configured frames and, on a GPU, at least kMinWarmupSeconds of them. A GPU's
  // clocks drop during the previous variant's CPU-side analysis; 30 frames of 2.5 ms once left the
  // first 6-7 measured frames 3x slow (H100, configs/depth-slices.json). warmup 0 means none.
  constexpr double kMinWarmupSeconds = 0.5;
  constexpr uint32_t kMaxWarmupFrames = 100000;  // the config's own limit on "warmup"
  const bool gpu = ctx.info().type != "cpu";
  const auto warmStart = std::chrono::steady_clock::now();
  auto warmSeconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - warmStart).count();
  };
  uint32_t warmed = 0;
  while (warmup > 0 && !gInterrupted && warmed < kMaxWarmupFrames &&
         (warmed < warmup || (gpu && warmSeconds() < kMinWarmupSeconds))) {
    renderer.renderFrame(false);
    ++warmed;
  }
  const double warmupSeconds = warmSeconds();
  std::vector<double> frameMs;
  std::map<std::string, std::vector<double>> passMs;
  std::vector<std::string> passOrder;
  for (uint32_t i = 0; i < measured && !gInterrupted; ++i) {
    FrameTiming t = renderer.renderFrame(false);
    frameMs.push_back(t.frameMs);
    for (const auto& [pass, ms] : t.passMs) {
      if (!passMs.count(pass)) passOrder.push_back(pass);
      passMs[pass].push_back(ms);
    }
  }
  if (gInterrupted) throw std::runtime_error("interrupted");
  renderer.renderFrame(true);  // analysis frame: counters, readbacks, images
  // Ray throughput right after it, while the GPU is as warm as in the measured frames (the CPU
  // analysis below takes seconds and lets the clocks drop): warm-up repetitions, then measured.
  std::vector<double> rb;
  if (ShadowsPart* shadows = shadowsOf(renderer)) {
    // 30 warm-up and 30 measured repetitions, fewer (at least 3) where one repetition is long: a
    // billion rays take most of a second, and 60 of them would be a minute per variant.
    const bool cpu = ctx.info().type == "cpu";
    const std::vector<double> first = shadows->rayBench(renderer.timer(), 1);
    constexpr double kRayBenchBudgetMs = 2000.0;
    const uint32_t reps =
        cpu ? 2u : uint32_t(std::clamp(kRayBenchBudgetMs / std::max(first.empty() ? 1.0 : first[0], 1e-3), 3.0, 30.0));
    shadows->rayBench(renderer.timer(), cpu ? 0 : reps - 1);
    rb = shadows->rayBench(renderer.timer(), reps);
  }
  RenderOutputs outputs = writeRenderOutputs(ctx, renderer, scene, v.params, imageDir, images, reference);

  json run = outputs.json;
  run["name"] = v.name;
  run["params"] = toJson(v.params);
  run["frames"] = measured;
  run["warmup_frames"] = warmed;  // rendered: at least the configured count (see above)
  run["warmup_s"] = warmupSeconds;
  Summary fs_ = summarize(frameMs);
  run["frame_ms"] = toJson(fs_, frameMs);
  run["passes"] = json::object();
  double sumOfMedians = 0;
  for (const std::string& pass : passOrder) {
    Summary s = summarize(passMs[pass]);
    run["passes"][pass] = toJson(s, passMs[pass]);
    sumOfMedians += s.median;
  }
  run["pass_order"] = passOrder;
  // What the frame spends outside the timed passes (barriers, gaps between passes).
  run["frame_minus_passes_ms"] = fs_.median - sumOfMedians;
  run["memory_bytes"] = memory;
  // Ray throughput: the analysis frame's own rays re-traced alone, against the shadow pass.
  if (!rb.empty() && run.contains("rays") && passMs.count("shadows")) {
    const size_t reps = rb.size();
    const double rays = run["rays"].value("traced", 0.0);
    const double benchMs = summarize(rb).median, shadowMs = summarize(passMs["shadows"]).median;
    run["raybench"] = {{"rays", rays},
                       {"repetitions", reps},
                       {"ms", toJson(summarize(rb), rb)},
                       {"rays_per_s", benchMs > 0 ? rays / (benchMs * 1e-3) : 0.0},
                       {"shadow_pass_rays_per_s", shadowMs > 0 ? rays / (shadowMs * 1e-3) : 0.0},
                       {"shadow_pass_fraction_of_peak", shadowMs > 0 ? benchMs / shadowMs : 0.0}};
  }
  run["scene"] = {{"triangles", scene.triangleCount()},
                  {"lights", scene.lights.size()},
                  {"camera_source", scene.cameraSource},
                  {"lights_source", scene.lightsSource}};
  if (!images) run.erase("images");
  run["status"] = "ok";
  return run;
}

}  // namespace

int sweepOneDevice(const SweepOptions& options, Config config, const DeviceInfo& device, const std::string& outDir,
                   const Console& console, const std::vector<std::string>& concurrent,
                   const std::vector<std::string>& sharing) {
  VulkanContext ctx(device.index);
  if (device.type == "cpu") {
    config = lowerForCpuDevice(config);
    console.print("note: " + config.notes.back() + "\n");
  }
  if (options.frames > 0) config.measuredFrames = uint32_t(options.frames);
  if (options.warmup >= 0) config.warmupFrames = uint32_t(options.warmup);
  std::vector<Variant> variants = expandVariants(config);
  fs::create_directories(outDir);
  const std::string resultsPath = (fs::path(outDir) / "results.json").string();

  // The scene of the config's defaults names the results file's scene (variants may scale it).
  SceneCache scenes;
  const Scene& baseScene = scenes.get(config, config.defaults);
  json results;
  results["schema_version"] = 1;
  json context;
  context["tool"] = {{"name", "hybridbench"}, {"version", toolVersion()}, {"git", gitRevision()}};
  context["host"] = hostJson();
  const std::string backend = ctx.info().rayQuery ? "rayquery" : ctx.info().rayTracingPipeline ? "pipeline" : "none";
  context["device"] = deviceJson(ctx.info(), backend);
  context["scene"] = {{"name", baseScene.name},
                      {"sha256", sceneSha256(baseScene)},
                      {"triangles", baseScene.triangleCount()},
                      {"lights", baseScene.lights.size()},
                      {"camera_source", baseScene.cameraSource},
                      {"lights_source", baseScene.lightsSource}};
  context["resolution"] = variants.front().params.resolution;
  context["config"] = toJson(config);
  context["frames"] = {{"warmup", config.warmupFrames}, {"measured", config.measuredFrames}};
  if (!concurrent.empty())
    context["concurrent_with"] = concurrent;  // other devices swept at the same time (one thread each)
  if (!sharing.empty())
    context["timing_caveat_shared_device"] =
        "this device also ran the sweep(s) of " + joinNames(sharing) +
        " at the same time: its times include their work; only the counts and accuracy are this sweep's own";
  context["timing_source"] =
      "Vulkan timestamp queries (per pass and per frame), masked to timestampValidBits, scaled by timestampPeriod";
  if (ctx.info().type == "cpu")
    context["timing_caveat"] =
        "CPU implementation (lavapipe): its timestamps do not bracket compute and ray-tracing work (those passes read "
        "~0.01 ms while the frame takes hundreds of ms), so per-pass times, shadow-pass shares and "
        "raybench.shadow_pass_fraction_of_peak are not meaningful here; frame times, counts and accuracy are.";
  results["context"] = context;
  results["runs"] = json::array();

  std::map<std::string, json> done;
  if (options.resume && fs::exists(resultsPath)) {
    std::ifstream f(resultsPath);
    json old;
    try {
      old = json::parse(f);
    } catch (const std::exception& e) {
      throw InputError(resultsPath + ": cannot resume, not valid JSON (" + e.what() +
                       "); remove it or use another --out");
    }
    const json& oc = old.value("context", json::object());
    if (oc.value("config", json()) != context["config"] ||
        oc.value("device", json::object()).value("uuid", "") != ctx.info().uuid)
      throw InputError(resultsPath +
                       ": --resume needs the same config (frame counts included) and device as the interrupted sweep; "
                       "use another --out");
    for (const json& run : old.value("runs", json::array()))
      if (run.value("status", "") == "ok") done[run.value("name", "")] = run;
    console.print(format("resume: %zu of %zu variants already done\n", done.size(), variants.size()));
  }

  console.print(format("sweep %s on %s: %zu variants, %u warm-up + %u measured frames each -> %s\n",
                       config.name.c_str(), ctx.info().name.c_str(), variants.size(), config.warmupFrames,
                       config.measuredFrames, outDir.c_str()));
  ReferenceCache references;
  Progress progress(variants.size(), console);
  size_t index = 0, failures = 0;
  for (const Variant& v : variants) {
    if (gInterrupted) break;
    progress.update(index, v.name);
    if (done.count(v.name)) {
      results["runs"].push_back(done[v.name]);
    } else {
      json run;
      try {
        run = runVariant(ctx, config, v, scenes, references, (fs::path(outDir) / slug(v.name)).string(), options.images,
                         config.warmupFrames, config.measuredFrames);
      } catch (const std::exception& e) {
        if (gInterrupted) break;  // the unfinished variant is not recorded; --resume runs it
        run = {{"name", v.name}, {"params", toJson(v.params)}, {"status", "error"}, {"error", e.what()}};
        ++failures;
        console.print(format("%svariant \"%s\" failed: %s\n", isatty(fileno(stdout)) && !console.shared() ? "\n" : "",
                             v.name.c_str(), e.what()));
      }
      results["runs"].push_back(run);
    }
    writeSweepOutputs(outDir, results);  // after every variant: nothing finished is ever lost
    ++index;
  }
  if (gInterrupted) {
    console.print(format("\ninterrupted: %zu of %zu variants written to %s; continue with --resume --out %s\n", index,
                         variants.size(), outDir.c_str(), outDir.c_str()));
    return 130;
  }
  progress.update(variants.size(), "done");
  if (!console.shared()) console.print(thesisTablesMarkdown(results));  // concurrent: in tables.md only
  console.print(format("wrote %s/results.json, results.csv, tables.md, accuracy.md, accuracy.svg%s\n", outDir.c_str(),
                       options.images ? " and images per variant" : ""));
  if (failures) console.print(format("%zu variant(s) failed: see status \"error\" in results.json\n", failures));
  if (ctx.validationMessages()) {
    std::fprintf(stderr, "hybridbench: %s%u validation message(s)\n",
                 console.shared() ? (device.name + ": ").c_str() : "", ctx.validationMessages());
    return kExitDeviceFailure;
  }
  return kExitOk;
}

void catchSweepInterrupts() {
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
}

bool sweepInterrupted() { return gInterrupted; }

}  // namespace hb
