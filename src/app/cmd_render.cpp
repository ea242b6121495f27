#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>

#include <nlohmann/json.hpp>

#include "analysis/render_outputs.h"
#include "app/auto_scene.h"
#include "app/commands.h"
#include "app/out_dir.h"
#include "app/run_context.h"
#include "app/scene_setup.h"
#include "base/errors.h"
#include "base/image_io.h"
#include "base/input_file.h"
#include "base/text_format.h"
#include "config/config.h"
#include "config/config_overrides.h"
#include "frame/ray_backend.h"
#include "frame/renderer.h"
#include "gltf/gltf_io.h"
#include "gpu/peaks.h"
#include "gpu/telemetry.h"
#include "gpu/vk_context.h"
#include "report/results_identity.h"
#include "report/roofline.h"
#include "scene/atrium.h"

namespace hb {

int cmdRender(const RenderOptions& options) {
  if (options.out.empty()) throw InputError("render: --out DIR is required (the directory the images and JSON go to)");
  // Earlier results in --out are refused before anything else (--force moves them aside below).
  if (!options.force) prepareOutDir(options.out, "render.json", Existing::Refuse, "render", false);
  requireOutputFolder(options.out, "render --out");
  // Parameters: the config's defaults (or the built-in ones), then --size, then each --set.
  Config config;
  bool haveConfig = !options.config.empty();
  if (haveConfig) config = loadConfig(options.config);
  VariantParams params = haveConfig ? config.defaults : VariantParams{};
  if (!options.size.empty()) {
    uint32_t w = 0, h = 0;
    parseSize(options.size, w, h, "--size");
    params.resolution = {w, h};
  }
  // Effects: the scene's own (planFrame adds them) < the config's < each --set that names one.
  EffectsRequest effects = haveConfig ? effectsRequestFor(config) : EffectsRequest{};
  bool cameraAuto = false;
  std::optional<Environment> environment;  // --set environment=...: replaces the config's and the scene's
  for (const std::string& set : options.sets) {
    if (isEffectSet(set)) {
      effects.layers.push_back(parseEffectSet(set));
      continue;
    }
    if (set.rfind("environment=", 0) == 0) {
      environment = environmentOfSet(set);
      continue;
    }
    if (set.rfind("camera=", 0) == 0) {
      if (set != "camera=auto")
        throw InputError("--set " + set +
                         ": the only camera setting is camera=auto (a camera framing the scene's "
                         "bounds); pick another of the scene's cameras with a config's \"camera\": {\"index\": N}");
      cameraAuto = true;
      continue;
    }
    applySetOverride(params, set);
  }
  const bool sceneFlagGiven = options.sceneGiven || !haveConfig;
  // What --set says, not an atrium config's own defaults (its scene_params), which do not carry
  // over to another --scene.
  bool setsTriangleScale = false, setsLightCount = false, setsCulling = false;
  for (const std::string& set : options.sets) {
    setsTriangleScale |= set.rfind("triangle_scale=", 0) == 0;
    setsLightCount |= set.rfind("light_count=", 0) == 0;
    setsCulling |= set.rfind("light_culling=", 0) == 0 || set.rfind("projection=", 0) == 0;
  }
  if (!(haveConfig && !sceneFlagGiven) && options.scene != "atrium" && setsTriangleScale)
    throw InputError("--set triangle_scale applies only to the built-in atrium, not to \"" + options.scene + "\"");
  Scene scene;
  if (haveConfig && !sceneFlagGiven) {
    if (cameraAuto) config.camera = CameraSpec{.autoFrame = true};
    checkParamsFitScene(config, params, "--set");
    scene = sceneForVariant(config, params);  // completes the scene itself
  } else {
    AutoRequest request;
    request.camera = cameraAuto;
    if (options.scene == "atrium") {
      AtriumParams ap;
      if (params.lightCount) ap.lightCount = *params.lightCount;
      if (params.triangleScale) ap.triangleScale = *params.triangleScale;
      scene = makeAtrium(ap);
    } else {
      scene = loadSceneArg(options.scene);
      if (setsLightCount) request.lightCount = params.lightCount;  // any other scene: that many automatic lights
    }
    for (const std::string& line : completeScene(scene, request)) std::fprintf(stderr, "%s\n", line.c_str());
  }
  if (environment) scene.environment = *environment;
  // A glTF's own orthographic camera: the light tiles are frusta of a perspective view (tile
  // culling for orthographic views is not built), so a run that did not ask for culling renders
  // it without, and says so; asking for it is the renderer's clear error.
  if (!haveConfig && !setsCulling && params.lightCulling && !scene.cameras.empty() &&
      scene.cameras[0].projection == CameraProjection::Orthographic && !params.projection) {
    params.lightCulling = false;
    std::fprintf(stderr,
                 "scene \"%s\": its camera is orthographic: light_culling=false (tile culling is built for "
                 "perspective views)\n",
                 scene.name.c_str());
  }
  RenderSettings settings = renderSettingsFor(params, effects);

  std::vector<DeviceInfo> devices = enumerateDevices();
  uint32_t deviceIndex = resolveDevice(devices, options.device);
  if (options.force) {  // after every other check: a refused run moves nothing
    const std::string aside = prepareOutDir(options.out, "render.json", Existing::Replace, "render", false);
    if (!aside.empty())
      std::printf("--force: moved the earlier files in %s to %s/\n", options.out.c_str(), aside.c_str());
  }
  std::filesystem::create_directories(options.out);
  VulkanContext ctx(deviceIndex);
  std::printf("device: %s (%s)\n", ctx.info().name.c_str(), ctx.info().driverInfo.c_str());
  std::printf("scene: %s, %s, %s, %ux%u\n", scene.name.c_str(), countOf(scene.triangleCount(), "triangle").c_str(),
              countOf(scene.lights.size(), "light").c_str(), settings.width, settings.height);
  std::fflush(stdout);
  // The device's ceilings (gpu/peaks.h), before the frame: backend=auto chooses from its ray rates.
  bool peaksCached = false;
  Peaks peaks = cachedPeaks(ctx, &peaksCached);
  addRayPeaks(ctx, scene, peaks, ctx.info().type != "cpu");
  for (const std::string& w : peaks.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  settings.rayRates = rayRatesOf(peaks, ctx.info(), settings.bvhWidth);
  Renderer renderer(ctx, scene, settings);
  if (!options.raysOut.empty()) {  // refused before any frame runs
    checkFrameRaysOut(renderer);
    requireOutputFolder(options.raysOut, "--rays-out");
    std::error_code ec;
    std::filesystem::create_directories(options.raysOut, ec);
    if (ec) throw InputError("--rays-out " + options.raysOut + ": cannot create it (" + ec.message() + ")");
  }
  renderer.renderFrame(false);  // warm: pipelines and caches
  // The device's clocks right before and after the timed frame (gpu/telemetry.h; NVIDIA only).
  const Telemetry telemetry = Telemetry::open(ctx.info());
  const std::optional<TelemetrySample> clocksBefore = telemetry.sample();
  FrameTiming timing = renderer.renderFrame(false);  // the timed frame: no instrumentation
  const std::optional<TelemetrySample> clocksAfter = telemetry.sample();
  renderer.renderFrame(true);  // the analysis frame (not timed)

  if (!options.raysOut.empty()) writeFrameRayFiles(renderer, options.raysOut);  // before the readbacks' analyses
  RenderOutputs outputs = writeRenderOutputs(ctx, renderer, scene, params, options.out);
  nlohmann::json report = outputs.json;
  report["timing_ms"] = nlohmann::json::object();
  for (const auto& [pass, ms] : timing.passMs) report["timing_ms"][pass] = ms;
  report["timing_ms"]["frame"] = timing.frameMs;
  report["frame_minus_passes_ms"] = frameMinusPassesMs(timing.frameMs, timing.passMs);
  nlohmann::json context = runContext(ctx, scene);
  context["resolution"] = {settings.width, settings.height};
  context["device"]["peaks"] = toJson(peaks, ctx.info());
  context["device"]["peaks"]["from_cache"] = peaksCached;
  context["device"]["telemetry"] = telemetry.deviceJson();
  report["context"] = context;
  report["telemetry"] = telemetry.measurementJson(clocksBefore, clocksAfter);
  if (const std::string w = results::throttleWarningOf(report); !w.empty())
    std::fprintf(stderr, "warning: %s\n", w.c_str());
  report["roofline"] =
      rooflineOf(renderer, report, std::map<std::string, double>(timing.passMs.begin(), timing.passMs.end()), peaks);
  report["params"] = toJson(params);
  report["camera"] = {{"source", scene.cameraSource}, {"name", scene.cameras.front().name}};
  report["lights"] = {{"source", scene.lightsSource}, {"count", scene.lights.size()}};
  const std::filesystem::path jsonPath = std::filesystem::path(options.out) / "render.json";
  {
    std::ofstream f(jsonPath.string() + ".tmp");
    f << report.dump(2) << "\n";
  }
  std::filesystem::rename(jsonPath.string() + ".tmp", jsonPath);

  for (const auto& [pass, ms] : timing.passMs) std::printf("%-20s %9.3f ms\n", pass.c_str(), ms);
  std::printf("%-20s %9.3f ms (GPU timestamps, one frame after a warm-up frame)\n", "frame", timing.frameMs);
  std::printf("%-20s %9.3f ms (barriers and gaps between passes)\n", "frame - passes",
              frameMinusPassesMs(timing.frameMs, timing.passMs));
  for (const auto& [pass, r] : report["roofline"].items())
    std::printf(
        "roofline %-18s %s: %s of %s%s\n", pass.c_str(), r["unit"].get<std::string>().c_str(),
        formatRate(r["achieved_per_s"].get<double>(), r["unit"]).c_str(),
        r["peak_per_s"].get<double>() > 0 ? formatRate(r["peak_per_s"].get<double>(), r["unit"]).c_str() : "no peak",
        r["fraction"].is_number() ? (" (" + peakFractionText(r["fraction"].get<double>()) + ")").c_str() : "");
  if (context.contains("timing_caveat"))
    std::printf("caveat: %s\n", context["timing_caveat"].get<std::string>().c_str());
  for (const EffectState& e : renderer.plan().effects)
    std::printf("effect %s: %s (%s%s%s)\n", e.name.c_str(),
                e.runs        ? "runs"
                : e.calledFor ? "called for, skipped"
                              : "off",
                toString(e.source), e.origin.empty() ? "" : ": ", e.origin.c_str());
  for (const EffectState& e : renderer.plan().effects)
    for (const std::string& note : e.notes) std::printf("note: %s\n", note.c_str());
  for (const auto& [pass, why] : renderer.passesSkipped()) std::printf("skipped %s: %s\n", pass.c_str(), why.c_str());
  for (const std::string& line : outputs.summary) std::printf("%s\n", line.c_str());
  std::printf("wrote %s (%zu files)\n", options.out.c_str(), outputs.files.size() + 1);
  if (ctx.validationMessages()) {
    std::fprintf(stderr, "hybridbench: %u validation message(s) (see above)\n", ctx.validationMessages());
    return kExitDeviceFailure;
  }
  return kExitOk;
}

}  // namespace hb
