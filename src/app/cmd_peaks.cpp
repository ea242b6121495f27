// `hybridbench peaks`: the device's own ceilings (gpu/peaks.h), printed as a table or as JSON, and
// written to the cache that sweeps and renders read (context.device.peaks).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "app/commands.h"
#include "base/errors.h"
#include "base/text_format.h"
#include "gpu/peaks.h"
#include "gpu/telemetry.h"
#include "report/results_identity.h"

namespace hb {

int cmdPeaks(const std::string& device, const std::string& scene, bool json) {
  const Scene rayScene = loadSceneArg(scene);  // a bad scene is one line before anything runs
  const std::vector<DeviceInfo> devices = enumerateDevices();
  const uint32_t index = resolveDevice(devices, device.empty() ? "0" : device);
  VulkanContext ctx(index);
  if (!json) std::fprintf(stderr, "peaks: measuring on %s ...\n", ctx.info().name.c_str());
  // The clocks before the warm-up and after the last figure (gpu/telemetry.h): whether the figures
  // were measured at a throttled speed. Printed with the figures, not cached.
  const Telemetry telemetry = Telemetry::open(ctx.info());
  const std::optional<TelemetrySample> before = telemetry.sample();
  Peaks peaks = measurePeaks(ctx);
  const nlohmann::json deviceOnly = toJson(peaks, ctx.info());
  addRayPeaks(ctx, rayScene, peaks);        // scene-dependent: printed, not cached
  addPublicRayPeaks(ctx, rayScene, peaks);  // the public tracers' three sets, beside them
  const std::optional<TelemetrySample> after = telemetry.sample();
  for (const std::string& w : peaks.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  nlohmann::json j = toJson(peaks, ctx.info());
  j["telemetry"] = telemetry.measurementJson(before, after);
  if (telemetry.available()) j["telemetry"]["device"] = telemetry.deviceJson();  // its highest clocks
  if (const std::string w = results::throttleWarningOf(j); !w.empty())
    std::fprintf(stderr, "warning: the peaks: %s\n", w.c_str());
  // The cache (gpu/peaks.h cachedPeaks) takes the fresh figures, so later sweeps use them.
  const std::string path = peaksCachePath(ctx.info());
  bool cached = false;
  if (!path.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(std::filesystem::path(path).parent_path(), ec);
    std::ofstream out(path);
    if (out) {
      out << deviceOnly.dump(2) << "\n";
      cached = bool(out);
    }
  }
  if (json) {
    std::cout << j.dump(2) << "\n";
  } else {
    std::printf("%s (%s), %s\n", ctx.info().name.c_str(), j["driver"].get<std::string>().c_str(), peaks.timing.c_str());
    std::printf("| figure | rate | median ms | what one repetition does |\n|---|---|---|---|\n");
    for (const Peak& p : peaks.figures)
      std::printf("| %s | %s | %.4g | %s |\n", p.key.c_str(), formatRate(p.perSecond, p.unit).c_str(),
                  j["figures"][p.key]["ms"]["median"].get<double>(), p.description.c_str());
    if (ctx.info().type == "cpu") std::printf("note: a CPU device: the figures are the host's, small but real\n");
    if (cached) std::printf("cached in %s (sweeps and renders on this device and driver read it)\n", path.c_str());
  }
  if (ctx.validationMessages()) {
    std::fprintf(stderr, "hybridbench: %u validation message(s)\n", ctx.validationMessages());
    return kExitDeviceFailure;
  }
  return kExitOk;
}

}  // namespace hb
