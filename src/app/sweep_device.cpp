#include "app/sweep_device.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <numeric>
#include <optional>
#include <sstream>

#include "analysis/render_outputs.h"
#include "app/run_context.h"
#include "app/scene_setup.h"
#include "app/sweep_results.h"
#include "app/sweep_resume.h"
#include "app/sweep_shard.h"
#include "app/sweep_worker.h"
#include "base/errors.h"
#include "base/text_format.h"
#include "base/version.h"
#include "effects/shadows/shadows_part.h"
#include "frame/ray_backend.h"
#include "frame/renderer.h"
#include "gltf/gltf_io.h"
#include "gpu/telemetry.h"
#include "gpu/vk_resources.h"
#include "gpu/warm_up.h"
#include "report/all_tables.h"
#include "report/results_identity.h"
#include "report/roofline.h"
#include "report/stats.h"
#include "report/tables.h"
#include "shared/gpu_types.h"

namespace hb {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

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
    if (params.referenceSsaa > 1) {  // the supersampled reference of the same frame
      const VariantParams rp = supersampledReferenceParams(params);
      const std::string key = "ssaa " + toJson(rp).dump();
      auto it = frames_.find(key);
      if (it == frames_.end()) {
        Renderer renderer(ctx, scene, renderSettingsFor(rp, effects));
        renderer.renderFrame(false);
        it = frames_.emplace(key, captureSupersampledReference(renderer, params.resolution[0], params.resolution[1]))
                 .first;
      }
      return &it->second;
    }
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

// Runs one variant; returns its run record (status ok) or throws. `telemetry` reads the device's
// clocks before and after the measured frames (run["telemetry"]).
json runVariant(const VulkanContext& ctx, const Config& config, const Variant& v, SceneCache& scenes,
                ReferenceCache& references, const std::string& imageDir, bool images, uint32_t warmup,
                uint32_t measured, const Peaks& peaks, const Telemetry& telemetry,
                const std::function<void(const char*)>& step) {
  step("scene");
  const Scene& scene = scenes.get(config, v.params);
  step("reference frame");
  const ReferenceFrame* reference = references.get(ctx, config, v.params, scenes);
  step("pipelines");
  RenderSettings settings = renderSettingsFor(v.params, effectsRequestFor(config));
  settings.rayRates = rayRatesOf(peaks, ctx.info(), settings.bvhWidth);  // what backend=auto chooses from
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
  step("warm-up");
  // Test only (docs/usage.md): the named variant stops making progress as a driver hang does,
  // deaf to SIGTERM, until the watchdog's SIGKILL; or its process ends on SIGABRT, as a crash.
  if (const char* hang = std::getenv("HYBRIDBENCH_TEST_HANG_VARIANT"); hang && v.name == hang)
    for (;;) ::pause();
  if (const char* crash = std::getenv("HYBRIDBENCH_TEST_CRASH_VARIANT"); crash && v.name == crash) std::abort();
  while (warmup > 0 && !gInterrupted && warmed < kMaxWarmupFrames &&
         (warmed < warmup || (gpu && warmSeconds() < kMinWarmupSeconds))) {
    renderer.renderFrame(false);
    ++warmed;
  }
  const double warmupSeconds = warmSeconds();
  std::vector<double> frameMs;
  std::map<std::string, std::vector<double>> passMs;
  std::vector<std::string> passOrder;
  step("measured frames");
  // The clocks, power, temperature and clocks event reasons right before and after the measured
  // frames (gpu/telemetry.h; outside them: each reading is a few NVML calls on the CPU).
  const std::optional<TelemetrySample> before = telemetry.sample();
  for (uint32_t i = 0; i < measured && !gInterrupted; ++i) {
    FrameTiming t = renderer.renderFrame(false);
    frameMs.push_back(t.frameMs);
    for (const auto& [pass, ms] : t.passMs) {
      if (!passMs.count(pass)) passOrder.push_back(pass);
      passMs[pass].push_back(ms);
    }
  }
  const std::optional<TelemetrySample> after = telemetry.sample();
  if (gInterrupted) throw std::runtime_error("interrupted");
  step("analysis frame");
  renderer.renderFrame(true);  // analysis frame: counters, readbacks, images
  // Ray throughput right after it, while the GPU is as warm as in the measured frames (the CPU
  // analysis below takes seconds and lets the clocks drop): warm-up repetitions, then measured.
  std::vector<double> rb;
  struct RayBenchRun {
    std::string backend;
    std::vector<double> ms;
    uint64_t pixelsDiffering;
  };
  std::vector<RayBenchRun> rbOthers;
  step("ray benchmark");
  if (ShadowsPart* shadows = shadowsOf(renderer)) {
    // 30 warm-up and 30 measured repetitions, fewer (at least 3) where one repetition is long: a
    // billion rays take most of a second, and 60 of them would be a minute per variant.
    const bool cpu = ctx.info().type == "cpu";
    const std::vector<double> first = shadows->rayBench(renderer.timer(), 1);
    constexpr double kRayBenchBudgetMs = 2000.0;
    const uint32_t reps =
        cpu ? 3u : uint32_t(std::clamp(kRayBenchBudgetMs / std::max(first.empty() ? 1.0 : first[0], 1e-3), 3.0, 30.0));
    shadows->rayBench(renderer.timer(), cpu ? 0 : reps - 1);
    rb = shadows->rayBench(renderer.timer(), reps);
    // The same rays through every other backend the device has, side by side (not on a CPU
    // device, whose timings do not bracket ray work): the rate and whether each ray's answer agrees.
    if (!cpu) {
      const std::vector<uint32_t> own = shadows->readRayBench();
      for (RtBackend b : shadows->rayBenchBackends()) {
        if (b == shadows->shadowPass().settings().backend) continue;
        shadows->rayBench(renderer.timer(), reps, b);  // warm-up
        RayBenchRun r{toString(b), shadows->rayBench(renderer.timer(), reps, b), 0};
        const std::vector<uint32_t> other = shadows->readRayBench(b);
        for (size_t i = 0; i < own.size() && i < other.size(); ++i) r.pixelsDiffering += own[i] != other[i];
        rbOthers.push_back(std::move(r));
      }
    }
  }
  step("analysis and images");
  RenderOutputs outputs = writeRenderOutputs(ctx, renderer, scene, v.params, imageDir, images, reference);

  json run = outputs.json;
  run["name"] = v.name;
  run["params"] = toJson(v.params);
  run["frames"] = measured;
  run["warmup_frames"] = warmed;  // rendered: at least the configured count (see above)
  run["warmup_s"] = warmupSeconds;
  run["telemetry"] = telemetry.measurementJson(before, after);  // with "warning" when it throttled
  Summary fs_ = summarize(frameMs);
  run["frame_ms"] = toJson(fs_, frameMs);
  run["passes"] = json::object();
  std::vector<std::pair<std::string, double>> medians;
  for (const std::string& pass : passOrder) {
    Summary s = summarize(passMs[pass]);
    run["passes"][pass] = toJson(s, passMs[pass]);
    medians.emplace_back(pass, s.median);
  }
  run["pass_order"] = passOrder;
  // What the frame spends outside the timed passes (barriers, gaps between passes).
  run["frame_minus_passes_ms"] = frameMinusPassesMs(fs_.median, medians);
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
    // Every backend on the same rays: the frame's first.
    json backends = json::object();
    backends[run.value("backend", std::string("?"))] = {{"ms", toJson(summarize(rb), rb)},
                                                        {"rays_per_s", benchMs > 0 ? rays / (benchMs * 1e-3) : 0.0},
                                                        {"pixels_differing", 0}};
    for (const RayBenchRun& r : rbOthers) {
      const double ms = summarize(r.ms).median;
      backends[r.backend] = {{"ms", toJson(summarize(r.ms), r.ms)},
                             {"rays_per_s", ms > 0 ? rays / (ms * 1e-3) : 0.0},
                             {"pixels_differing", r.pixelsDiffering}};
    }
    run["raybench"]["backends"] = backends;
    run["raybench"]["backends_source"] =
        rbOthers.empty() && ctx.info().type == "cpu"
            ? "the frame's backend only (a CPU device: other backends are not timed)"
            : "the analysis frame's shadow rays through each backend, as many repetitions each; pixels_differing: "
              "pixels whose count of visible rays differs from the frame backend's";
  }
  // Each timed pass against the device's own ceilings (report/roofline.h).
  std::map<std::string, double> medianMs(medians.begin(), medians.end());
  run["roofline"] = rooflineOf(renderer, run, medianMs, peaks);
  run["scene"] = {{"triangles", scene.triangleCount()},
                  {"lights", scene.lights.size()},
                  {"camera_source", scene.cameraSource},
                  {"lights_source", scene.lightsSource}};
  if (!images) run.erase("images");
  run["status"] = "ok";
  return run;
}

}  // namespace

Config configForDevice(Config config, const SweepOptions& options, const DeviceInfo& device) {
  // --frames/--warmup win over the config and over a CPU device's lower counts; the note says which.
  CpuFrameOverrides given;
  if (options.frames > 0) given.measured = config.measuredFrames = uint32_t(options.frames);
  if (options.warmup >= 0) given.warmup = config.warmupFrames = uint32_t(options.warmup);
  if (device.type == "cpu") config = lowerForCpuDevice(config, given);
  return config;
}

void printDryRun(const SweepOptions& options, Config config, const DeviceInfo& device, const std::string& outDir) {
  const Config asGiven = config;
  config = configForDevice(config, options, device);
  const std::vector<Variant> all = expandVariants(config);
  std::vector<size_t> positions(all.size());  // the variants this sweep runs: all, or its --shard's
  for (size_t k = 0; k < all.size(); ++k) positions[k] = k;
  std::string part;
  if (!options.shard.empty()) {
    const ShardSpec spec = parseShard(options.shard);
    SceneCache probe;
    const ShardPlan plan =
        planShards(asGiven, expandVariants(asGiven), probe.get(config, config.defaults).lights.size(), spec.count);
    positions = plan.parts[spec.index];
    const double total = std::accumulate(plan.partCosts.begin(), plan.partCosts.end(), 0.0);
    std::printf("shard %zu/%zu: %zu of %zu variants; every part's estimated cost (%s):\n", spec.index, spec.count,
                positions.size(), all.size(), shardContext(spec, plan, all)["cost_model"].get<std::string>().c_str());
    for (size_t p = 0; p < spec.count; ++p)
      std::printf("  part %zu/%zu: %s, cost %.4g (%.1f %%)%s\n", p, spec.count,
                  countOf(plan.parts[p].size(), "variant").c_str(), plan.partCosts[p],
                  total > 0 ? 100.0 * plan.partCosts[p] / total : 0.0, p == spec.index ? "  <- this part" : "");
    part = format(" (shard %zu/%zu)", spec.index, spec.count);
  }
  std::vector<Variant> variants;
  for (size_t k : positions) variants.push_back(all[k]);
  std::printf("dry run: nothing is written (to %s or anywhere); a few frames render for the estimate\n",
              outDir.c_str());
  std::printf("sweep %s%s on %s: %s, %u warm-up + %u measured frames each\n", config.name.c_str(), part.c_str(),
              device.name.c_str(), countOf(variants.size(), "variant").c_str(), config.warmupFrames,
              config.measuredFrames);
  if (variants.empty()) {
    std::printf("this part is empty (more parts than variants): its sweep writes a results.json without runs\n");
    return;
  }
  if (device.type == "cpu") std::printf("note: %s\n", config.notes.back().c_str());
  std::printf("scene: %s\n", config.scene.c_str());
  const json defaults = toJson(config.defaults);
  std::printf("defaults: %s\n", defaults.dump().c_str());
  for (size_t i = 0; i < variants.size(); ++i) {
    json diff = json::object();  // what this variant sets beyond the defaults
    const json params = toJson(variants[i].params);
    for (auto it = params.begin(); it != params.end(); ++it)
      if (!defaults.contains(it.key()) || defaults[it.key()] != it.value()) diff[it.key()] = it.value();
    std::printf("%4zu. %s: %s\n", positions[i] + 1, variants[i].name.c_str(),
                diff.empty() ? "(the defaults)" : diff.dump().c_str());
  }
  const uint64_t frames = uint64_t(variants.size()) * (config.warmupFrames + config.measuredFrames + 1);
  std::printf("frames: %llu (%zu x (%u + %u + 1 analysis))\n", (unsigned long long)frames, variants.size(),
              config.warmupFrames, config.measuredFrames);
  // The estimate: a few frames of the first variant on this device, scaled by each variant's pixel
  // count; a GPU warms up for at least 0.5 s a variant (runVariant). Analysis frames (CPU-side
  // references, seconds each) are not in it.
  try {
    VulkanContext ctx(device.index);
    SceneCache scenes;
    const Variant& first = variants.front();
    const Scene& scene = scenes.get(config, first.params);
    Renderer renderer(ctx, scene, renderSettingsFor(first.params, effectsRequestFor(config)));
    renderer.renderFrame(false);
    constexpr int kProbeFrames = 3;
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < kProbeFrames; ++i) renderer.renderFrame(false);
    const double frameS =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / kProbeFrames;
    const double pixels0 = double(first.params.resolution[0]) * first.params.resolution[1];
    double total = 0;
    for (const Variant& v : variants) {
      const double scale = double(v.params.resolution[0]) * v.params.resolution[1] / pixels0;
      double warm = config.warmupFrames * frameS * scale;
      if (device.type != "cpu" && config.warmupFrames > 0) warm = std::max(warm, 0.5);
      total += warm + (config.measuredFrames + 1) * frameS * scale;
    }
    std::printf(
        "estimate: ~%.1f s of rendering (%.1f ms a frame for the first variant here, scaled by each variant's pixel "
        "count), plus each variant's analysis (seconds on a CPU device), which this does not estimate\n",
        total, frameS * 1e3);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    std::printf("estimate: unavailable (the first variant did not render: %s)\n", e.what());
  }
}

// The variant positions of "0,3,4" (--worker-variants).
static std::vector<size_t> parsePositions(const std::string& list, size_t count) {
  std::vector<size_t> out;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');) {
    const size_t k = std::stoul(item);
    if (k >= count) throw InputError("--worker-variants: no variant " + item);
    out.push_back(k);
  }
  return out;
}

int runSweepWorker(const SweepOptions& options, Config config, const DeviceInfo& device, const std::string& outDir) {
  const WorkerChannel parent(options.workerFd);
  VulkanContext ctx(device.index);
  config = configForDevice(config, options, device);
  const std::vector<Variant> variants = expandVariants(config);
  SceneCache scenes;
  const Scene& baseScene = scenes.get(config, config.defaults);
  json context = runContext(ctx, baseScene);
  context["resolution"] = variants.front().params.resolution;
  context.update(inputsContext(config, options.config, options.sets), /*merge_objects=*/true);
  context["frames"] = {{"warmup", config.warmupFrames}, {"measured", config.measuredFrames}};
  // The device's own ceilings, measured once per device and driver (gpu/peaks.h: cached).
  bool peaksCached = false;
  Peaks peaks = cachedPeaks(ctx, &peaksCached);
  addRayPeaks(ctx, baseScene, peaks, ctx.info().type != "cpu");  // the scene's own: never cached
  for (const std::string& w : peaks.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  context["device"]["peaks"] = toJson(peaks, ctx.info());
  context["device"]["peaks"]["from_cache"] = peaksCached;
  // A steady device before the first variant (gpu/warm_up.h): cached peaks measured nothing here,
  // and a device that idled while the CPU loaded the scene runs its first frames at other clocks.
  const WarmUp warm = warmDevice(ctx);
  context["device"]["warm_up"] = toJson(warm);
  if (const std::string w = warmUpWarning(warm); !w.empty()) {
    std::fprintf(stderr, "warning: %s\n", w.c_str());
    context["device"]["warm_up"]["warning"] = w;
  }
  // NVML, open for all of this worker's variants (gpu/telemetry.h): unavailable, with its reason,
  // on a device that is not NVIDIA or without the NVIDIA driver.
  const Telemetry telemetry = Telemetry::open(ctx.info());
  context["device"]["telemetry"] = telemetry.deviceJson();
  parent.send("context", context.dump());
  ReferenceCache references;  // across the variants of this worker
  for (const size_t k : parsePositions(options.workerVariants, variants.size())) {
    if (gInterrupted) break;
    const Variant& v = variants[k];
    parent.send("variant", std::to_string(k));
    json run;
    try {
      run = runVariant(ctx, config, v, scenes, references, (fs::path(outDir) / slug(v.name)).string(), options.images,
                       config.warmupFrames, config.measuredFrames, peaks, telemetry,
                       [&](const char* what) { parent.send("step", what); });
    } catch (const std::exception& e) {
      if (gInterrupted) break;  // the unfinished variant is not recorded; --resume runs it
      run = {{"name", v.name}, {"params", toJson(v.params)}, {"status", "error"}, {"error", e.what()}};
    }
    parent.send("run", run.dump());
  }
  parent.send("validation", std::to_string(ctx.validationMessages()));
  return gInterrupted ? 130 : kExitOk;
}

namespace {

// The command line of a worker for `positions` of this sweep on `device`.
std::vector<std::string> workerArgs(const SweepOptions& options, const DeviceInfo& device, const std::string& outDir,
                                    const std::vector<size_t>& positions) {
  std::vector<std::string> a = {"sweep"};
  if (!options.config.empty()) a.push_back(options.config);
  a.insert(a.end(), {"--device", std::to_string(device.index), "--out", outDir});
  appendRunOptions(a, options);
  std::string list;
  for (size_t k : positions) list += (list.empty() ? "" : ",") + std::to_string(k);
  a.insert(a.end(), {"--worker-fd", std::to_string(kWorkerFd), "--worker-variants", list});
  return a;
}

}  // namespace

int sweepOneDevice(const SweepOptions& options, Config config, const DeviceInfo& device, const std::string& outDir,
                   const Console& console, const std::vector<std::string>& concurrent,
                   const std::vector<std::string>& sharing) {
  const Config asGiven = config;  // what a worker starts from
  config = configForDevice(config, options, device);
  std::vector<Variant> variants = expandVariants(config);
  // The scene of the config's defaults names the results file's scene (variants may scale it). It
  // loads before anything is printed or created: a scene refused is one line and no folder.
  SceneCache scenes;
  const Scene& baseScene = scenes.get(config, config.defaults);
  const size_t sceneLights = baseScene.lights.size();
  // The variants this sweep runs: all, or the part --shard names. The parts are planned on the
  // config as given, before a CPU device lowers it, so every machine of a fleet plans the same.
  std::vector<bool> mine(variants.size(), true);
  json shard;  // context.shard
  std::string part;
  if (!options.shard.empty()) {
    const ShardSpec spec = parseShard(options.shard);
    const ShardPlan plan = planShards(asGiven, expandVariants(asGiven), sceneLights, spec.count);
    mine.assign(variants.size(), false);
    for (size_t k : plan.parts[spec.index]) mine[k] = true;
    shard = shardContext(spec, plan, variants);
    part = format(" (shard %zu/%zu)", spec.index, spec.count);
  }
  const size_t mineCount = size_t(std::count(mine.begin(), mine.end(), true));
  if (device.type == "cpu") console.print("note: " + config.notes.back() + "\n");
  fs::create_directories(outDir);
  const std::string resultsPath = (fs::path(outDir) / "results.json").string();
  const uint64_t framesPerVariant = uint64_t(config.warmupFrames) + config.measuredFrames + 1;
  const double timeoutS = options.variantTimeout > 0
                              ? options.variantTimeout
                              : std::max(kVariantTimeoutFloorS, kFrameLimitS * double(framesPerVariant));

  // Each position's run once known: finished earlier (--resume) or now.
  std::vector<json> slots(variants.size());
  json resumedContext;
  if (options.resume && fs::exists(resultsPath)) {
    json inputs = inputsContext(config, options.config, options.sets);
    inputs["scene"]["sha256"] = sceneSha256(baseScene);
    ResumedResults resumed = readResumable(resultsPath, inputs, device, shard, options.retryFailed);
    for (const std::string& w : resumed.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    resumedContext = std::move(resumed.context);  // until a worker sends today's
    std::map<std::string, json>& kept = resumed.kept;
    for (size_t k = 0; k < variants.size(); ++k)
      if (mine[k] && kept.count(variants[k].name)) slots[k] = kept[variants[k].name];
    size_t done = 0, failed = 0;
    for (const json& run : slots)
      if (!run.is_null()) (run.value("status", "") == "ok" ? done : failed)++;
    console.print(format(
        "resume: %zu of %zu variants already done%s\n", done, mineCount,
        failed ? format(", %zu that timed out or crashed kept (--retry-failed runs them again)", failed).c_str() : ""));
  }

  console.print(format("sweep %s%s on %s: %s, %u warm-up + %u measured frames each -> %s\n", config.name.c_str(),
                       part.c_str(), device.name.c_str(), countOf(mineCount, "variant").c_str(), config.warmupFrames,
                       config.measuredFrames, outDir.c_str()));
  json results;
  results["schema_version"] = 1;
  results["runs"] = json::array();
  if (!resumedContext.is_null()) results["context"] = resumedContext;
  auto write = [&] {
    results["runs"] = json::array();
    for (const json& run : slots)
      if (!run.is_null()) results["runs"].push_back(run);
    if (results.contains("context")) writeSweepOutputs(outDir, results);  // nothing finished is ever lost
  };
  // The clock of "elapsed" and "eta" starts when the first worker has its device (as it did when
  // the sweep opened the device itself).
  std::optional<Progress> progress;
  size_t finished = 0, failures = 0;
  for (const json& run : slots) finished += !run.is_null();
  unsigned validation = 0;
  bool interrupted = false;
  // Workers, one after another: each runs the variants still to do until they are done or it
  // ends; a variant it did not finish is recorded and the next worker starts after it.
  bool contextAsked = false;
  while (!interrupted) {
    std::vector<size_t> todo;
    for (size_t k = 0; k < variants.size(); ++k)
      if (mine[k] && slots[k].is_null()) todo.push_back(k);
    // An empty part (more parts than variants) still starts one worker, with no variants, for the
    // context (device, scene, revision) that `merge` checks.
    if (todo.empty() && (results.contains("context") || contextAsked)) break;
    contextAsked = true;
    const std::vector<std::string> args = workerArgs(options, device, outDir, todo);
    WorkerProcess worker(args, [&](int fd) {
      SweepOptions o = options;
      o.workerFd = fd;
      o.workerVariants = args.back();  // "--worker-variants LIST" ends the arguments
      return runSweepWorker(o, asGiven, device, outDir);
    });
    long current = -1;  // the position in flight
    std::string lastStep = "start";
    auto started = std::chrono::steady_clock::now();
    auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(); };
    bool progressed = false, timedOut = false;
    for (;;) {
      if (gInterrupted) {
        interrupted = true;
        break;
      }
      std::string kind, payload;
      const double left = current >= 0 ? timeoutS - seconds() : 1e9;
      const WorkerProcess::Read r = worker.next(std::min(1.0, std::max(left, 0.0)), kind, payload);
      if (r == WorkerProcess::Read::End) break;
      if (r == WorkerProcess::Read::Timeout) {
        if (current >= 0 && seconds() >= timeoutS && !worker.isThread()) {  // a thread cannot be ended
          timedOut = true;
          break;
        }
        continue;
      }
      if (kind == "context") {
        json context = json::parse(payload);
        if (!concurrent.empty())
          context["concurrent_with"] = concurrent;  // other devices swept at the same time (one thread each)
        if (!sharing.empty())
          context["timing_caveat_shared_device"] =
              "this device also ran the sweep(s) of " + joinNames(sharing) +
              " at the same time: its times include their work; only the counts and accuracy are this sweep's own";
        if (shard.is_object()) context["shard"] = shard;
        results["context"] = context;
        if (!progress) progress.emplace(mineCount, console);
      } else if (kind == "variant") {
        current = std::stol(payload);
        lastStep = "start";
        started = std::chrono::steady_clock::now();
        progressed = true;
        if (progress) progress->update(finished, variants[size_t(current)].name);
      } else if (kind == "step") {
        lastStep = payload;
      } else if (kind == "run" && current >= 0) {
        json run = json::parse(payload);
        if (run.value("status", "") == "error") {
          ++failures;
          console.print(format("%svariant \"%s\" failed: %s\n", isatty(fileno(stdout)) && !console.shared() ? "\n" : "",
                               variants[size_t(current)].name.c_str(), run.value("error", "").c_str()));
        }
        if (const std::string w = results::throttleWarningOf(run); !w.empty())
          std::fprintf(
              stderr, "%swarning: %svariant \"%s\": %s\n", isatty(fileno(stdout)) && !console.shared() ? "\n" : "",
              console.shared() ? (device.name + ": ").c_str() : "", variants[size_t(current)].name.c_str(), w.c_str());
        slots[size_t(current)] = run;
        ++finished;
        current = -1;
        write();
      } else if (kind == "validation") {
        validation += unsigned(std::stoul(payload));
      }
    }
    if (interrupted) {
      worker.stop(kWorkerGraceS);  // it stops after its frame (Ctrl-C reached it too) or is killed
      break;
    }
    const double ranS = seconds();  // before the grace period
    const int status = timedOut ? worker.stop(kWorkerGraceS) : worker.wait();
    if (current < 0) {
      if (WIFEXITED(status) && WEXITSTATUS(status) == kExitOk) continue;  // it ran all it was given
      if (!progressed) {
        // It ended before its first variant (the device would not open, ...): its error is on
        // stderr already; a fresh worker would end the same way.
        std::fprintf(stderr, "hybridbench: the sweep's worker process ended before its first variant (%s)\n",
                     describeWaitStatus(status).c_str());
        write();
        return WIFEXITED(status) && WEXITSTATUS(status) != 0 ? WEXITSTATUS(status) : kExitDeviceFailure;
      }
      continue;  // between variants: the next worker goes on
    }
    const Variant& v = variants[size_t(current)];
    json run = {{"name", v.name},
                {"params", toJson(v.params)},
                {"status", timedOut ? "timeout" : "crashed"},
                {"last_step", lastStep},
                {"seconds", ranS},
                {"process", describeWaitStatus(status)}};
    if (timedOut) run["timeout_s"] = timeoutS;
    slots[size_t(current)] = run;
    ++finished;
    console.print(
        format("%svariant \"%s\" %s after %.0f s in step \"%s\" (%s); the sweep goes on with a fresh device\n",
               isatty(fileno(stdout)) && !console.shared() ? "\n" : "", v.name.c_str(),
               timedOut ? "timed out" : "crashed", ranS, lastStep.c_str(), describeWaitStatus(status).c_str()));
    write();
  }
  if (interrupted || gInterrupted) {
    write();
    console.print(
        "\n" + format("interrupted: %zu of %zu variants written to %s; ", finished, mineCount, outDir.c_str()) +
        "continue with: " + resumeCommand(options, device, outDir, console.shared(), options.retryFailed) + "\n");
    return 130;
  }
  write();
  if (!progress) progress.emplace(mineCount, console);
  progress->update(mineCount, "done");
  if (!console.shared()) console.print(allTablesMarkdown(results));  // concurrent: in tables.md only
  console.print(
      format("wrote %s/report.html (one page with everything: open it), results.json, results.csv, tables.md, "
             "accuracy.md, accuracy.svg%s\n",
             outDir.c_str(), options.images ? " and images per variant" : ""));
  if (failures) console.print(format("%zu variant(s) failed: see status \"error\" in results.json\n", failures));
  size_t lost = 0;               // this sweep's and those --resume kept
  for (const json& run : slots)  // null: another part's variant (--shard)
    lost += run.is_object() && (run.value("status", "") == "timeout" || run.value("status", "") == "crashed");
  if (lost) {
    std::fprintf(stderr,
                 "hybridbench: %s%zu variant(s) timed out or crashed (status \"timeout\" or \"crashed\" in "
                 "results.json); every other variant finished; run them again with: %s\n",
                 console.shared() ? (device.name + ": ").c_str() : "", lost,
                 resumeCommand(options, device, outDir, console.shared(), true).c_str());
    return kExitDeviceFailure;
  }
  if (validation) {
    std::fprintf(stderr, "hybridbench: %s%u validation message(s)\n",
                 console.shared() ? (device.name + ": ").c_str() : "", validation);
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
