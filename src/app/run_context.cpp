#include "app/run_context.h"

#include <unistd.h>

#include <sys/utsname.h>
#include <ctime>
#include <filesystem>
#include <fstream>

#include "base/sha256.h"
#include "base/version.h"
#include "gltf/gltf_io.h"

namespace hb {

using json = nlohmann::json;

const char* const kCpuTimingCaveat =
    "CPU implementation (lavapipe): its timestamps do not bracket compute and ray-tracing work (those passes read "
    "~0.01 ms while the frame takes hundreds of ms), so per-pass times, shadow-pass shares and "
    "raybench.shadow_pass_fraction_of_peak are not meaningful here; frame times, counts and accuracy are.";

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

}  // namespace

json runContext(const VulkanContext& ctx, const Scene& scene) {
  json context;
  context["tool"] = {{"name", "hybridbench"}, {"version", toolVersion()}, {"git", gitRevision()}};
  context["host"] = hostJson();
  const std::string backend = ctx.info().rayQuery ? "rayquery" : ctx.info().rayTracingPipeline ? "pipeline" : "none";
  context["device"] = deviceJson(ctx.info(), backend);
  context["scene"] = {{"name", scene.name},
                      {"sha256", sceneSha256(scene)},
                      {"triangles", scene.triangleCount()},
                      {"lights", scene.lights.size()},
                      {"camera_source", scene.cameraSource},
                      {"lights_source", scene.lightsSource}};
  context["timing_source"] =
      "Vulkan timestamp queries (per pass and per frame), masked to timestampValidBits, scaled by timestampPeriod";
  if (ctx.info().type == "cpu") context["timing_caveat"] = kCpuTimingCaveat;
  return context;
}

json inputsContext(const Config& config, const std::string& configFile, const std::vector<std::string>& sets) {
  json inputs = {{"config", toJson(config)}};
  if (!configFile.empty()) inputs["config_file"] = std::filesystem::absolute(configFile).lexically_normal().string();
  if (!sets.empty()) inputs["overrides"] = {{"set", sets}};
  if (config.environment && !config.environment->image.empty()) {
    const Environment& e = *config.environment;
    Sha256 sha;
    const uint32_t size[2] = {e.width, e.height};  // little-endian, as sceneSha256 writes values
    sha.update(size, sizeof size);
    sha.update(e.texels.data(), e.texels.size() * sizeof(e.texels[0]));
    inputs["scene"] = {{"environment_sha256", sha.hexDigest()}};
  }
  return inputs;
}

double frameMinusPassesMs(double frameMs, const std::vector<std::pair<std::string, double>>& passMs) {
  double sum = 0;
  for (const auto& [pass, ms] : passMs)
    if (pass.find('.') == std::string::npos) sum += ms;
  return frameMs - sum;
}

}  // namespace hb
