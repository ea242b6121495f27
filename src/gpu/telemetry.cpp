#include "gpu/telemetry.h"
#include "base/text_format.h"

#include <dlfcn.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

namespace hb {

using json = nlohmann::json;

// The part of NVML's C API this file calls, in a named namespace: Telemetry::Nvml holds these
// types, and a member of a type with linkage may not have a type of the anonymous namespace.
namespace nvml {

// The part of NVML's C API this file calls, declared from the NVML API reference
// (docs.nvidia.com/deploy/nvml-api): no NVML header is needed to build. nvmlReturn_t,
// nvmlClockType_t and nvmlTemperatureSensors_t are C enums (int-sized); nvmlDevice_t is an opaque
// pointer.
using NvmlReturn = int;
constexpr NvmlReturn kNvmlSuccess = 0;                    // NVML_SUCCESS
constexpr NvmlReturn kNvmlErrorNotFound = 6;              // NVML_ERROR_NOT_FOUND
using NvmlDevice = struct NvmlDeviceOpaque*;              // nvmlDevice_t
using NvmlClockType = int;                                // nvmlClockType_t
constexpr NvmlClockType kNvmlClockSm = 1;                 // NVML_CLOCK_SM
constexpr NvmlClockType kNvmlClockMem = 2;                // NVML_CLOCK_MEM
using NvmlTemperatureSensor = int;                        // nvmlTemperatureSensors_t
constexpr NvmlTemperatureSensor kNvmlTemperatureGpu = 0;  // NVML_TEMPERATURE_GPU
constexpr unsigned kNvmlUuidBufferSize = 96;              // NVML_DEVICE_UUID_V2_BUFFER_SIZE

}  // namespace nvml

namespace {

constexpr uint32_t kNvidiaVendorId = 0x10DE;  // VkPhysicalDeviceProperties::vendorID (PCI vendor)

const double kNotRead = std::numeric_limits<double>::quiet_NaN();

// NaN (not read) as null; a whole number (MHz, degrees) as an integer, "1980" rather than "1980.0".
json numberOrNull(double v) {
  if (std::isnan(v)) return nullptr;
  if (v == std::floor(v) && std::fabs(v) < 1e15) return int64_t(v);
  return v;
}

std::string hexText(uint64_t v) {
  char s[24];
  std::snprintf(s, sizeof s, "0x%llx", static_cast<unsigned long long>(v));
  return s;
}

}  // namespace

std::vector<std::string> clockReasonNames(uint64_t mask) {
  static constexpr std::pair<uint64_t, const char*> kNames[] = {
      {kClockReasonGpuIdle, "gpu_idle"},
      {kClockReasonApplicationsClocksSetting, "applications_clocks_setting"},
      {kClockReasonSwPowerCap, "sw_power_cap"},
      {kClockReasonHwSlowdown, "hw_slowdown"},
      {kClockReasonSyncBoost, "sync_boost"},
      {kClockReasonSwThermalSlowdown, "sw_thermal_slowdown"},
      {kClockReasonHwThermalSlowdown, "hw_thermal_slowdown"},
      {kClockReasonHwPowerBrakeSlowdown, "hw_power_brake_slowdown"},
      {kClockReasonDisplayClockSetting, "display_clock_setting"},
      {kClockReasonBoardLimit, "board_limit"},
      {kClockReasonReliability, "reliability"},
  };
  std::vector<std::string> names;
  for (int b = 0; b < 64; ++b) {
    const uint64_t bit = uint64_t(1) << b;
    if (!(mask & bit)) continue;
    const char* name = nullptr;
    for (const auto& [value, n] : kNames)
      if (value == bit) name = n;
    names.push_back(name ? name : "bit_" + hexText(bit));
  }
  return names;
}

// Which reasons make a measurement "throttled": the ones that lower the clocks because of the
// device's state, which varies with the load, the temperature, the cooling and how long the device
// has run, so that the same work times differently from one run to the next: a power cap
// (sw_power_cap, hw_power_brake_slowdown, board_limit), heat (sw_thermal_slowdown,
// hw_thermal_slowdown), a hardware slowdown (hw_slowdown), reliability, and any bit NVML adds later
// (counted until known to be harmless). The others are not:
// - gpu_idle: nothing ran at that instant (a reading between submissions); it says nothing of the
//   clocks the work ran at.
// - applications_clocks_setting, display_clock_setting: clocks fixed by a setting (nvidia-smi -ac,
//   the display clocks), the same in every run on that setting: what a CI that pins its clocks
//   wants, not a change of speed.
// - sync_boost: clocks held to the slowest GPU of a sync-boost group, a setting too.
uint64_t throttlingReasons(uint64_t mask) { return mask & ~kBenignClockReasons; }

bool throttled(const TelemetrySample& before, const TelemetrySample& after) {
  return throttlingReasons(before.throttleReasons | after.throttleReasons) != 0;
}

json toJson(const TelemetrySample& s) {
  json j = {{"sm_clock_mhz", numberOrNull(s.smClockMHz)},
            {"memory_clock_mhz", numberOrNull(s.memClockMHz)},
            {"power_w", numberOrNull(s.powerW)},
            {"temperature_c", numberOrNull(s.temperatureC)}};
  j["clock_reasons_mask"] = s.throttleReasonsRead ? json(s.throttleReasons) : json(nullptr);
  j["clock_reasons"] = s.throttleReasonsRead ? json(s.throttleNames) : json(nullptr);
  return j;
}

json toJson(const TelemetrySample& before, const TelemetrySample& after) {
  json j = {{"available", true}, {"before", toJson(before)}, {"after", toJson(after)}};
  const bool slowed = throttled(before, after);
  const bool known = before.throttleReasonsRead && after.throttleReasonsRead;
  j["throttled"] = slowed || known ? json(slowed) : json(nullptr);
  j["throttle_reasons"] = clockReasonNames(throttlingReasons(before.throttleReasons | after.throttleReasons));
  if (const std::string w = throttleWarning(before, after); !w.empty()) j["warning"] = w;
  return j;
}

json unavailableTelemetryJson(const std::string& reason) { return {{"available", false}, {"reason", reason}}; }

std::string throttleWarning(const TelemetrySample& before, const TelemetrySample& after) {
  if (!throttled(before, after)) return "";
  std::string reasons;
  for (const std::string& n : clockReasonNames(throttlingReasons(before.throttleReasons | after.throttleReasons)))
    reasons += (reasons.empty() ? "" : ", ") + n;
  auto mhz = [](double v) { return std::isnan(v) ? std::string("?") : std::to_string(std::lround(v)); };
  return "the GPU's clocks were held down while it was measured (" + reasons + "; SM clock " + mhz(before.smClockMHz) +
         " MHz before, " + mhz(after.smClockMHz) +
         " MHz after): its times depend on the device's power and temperature, not on its work alone";
}

// NVML's entry points, resolved by name from the loaded library.
struct Telemetry::Nvml {
  void* library = nullptr;  // dlopen's handle
  bool initialised = false;
  nvml::NvmlDevice device = nullptr;
  nvml::NvmlReturn (*init)() = nullptr;                                        // nvmlInit_v2
  nvml::NvmlReturn (*shutdown)() = nullptr;                                    // nvmlShutdown
  const char* (*errorString)(nvml::NvmlReturn) = nullptr;                      // nvmlErrorString
  nvml::NvmlReturn (*handleByUuid)(const char*, nvml::NvmlDevice*) = nullptr;  // nvmlDeviceGetHandleByUUID
  nvml::NvmlReturn (*count)(unsigned*) = nullptr;                              // nvmlDeviceGetCount_v2
  nvml::NvmlReturn (*handleByIndex)(unsigned, nvml::NvmlDevice*) = nullptr;    // nvmlDeviceGetHandleByIndex_v2
  nvml::NvmlReturn (*uuid)(nvml::NvmlDevice, char*, unsigned) = nullptr;       // nvmlDeviceGetUUID
  nvml::NvmlReturn (*clock)(nvml::NvmlDevice, nvml::NvmlClockType, unsigned*) = nullptr;  // nvmlDeviceGetClockInfo
  nvml::NvmlReturn (*maxClock)(nvml::NvmlDevice, nvml::NvmlClockType,
                               unsigned*) = nullptr;                 // nvmlDeviceGetMaxClockInfo
  nvml::NvmlReturn (*power)(nvml::NvmlDevice, unsigned*) = nullptr;  // nvmlDeviceGetPowerUsage, mW
  nvml::NvmlReturn (*temperature)(nvml::NvmlDevice, nvml::NvmlTemperatureSensor,
                                  unsigned*) = nullptr;  // nvmlDeviceGetTemperature
  // nvmlDeviceGetCurrentClocksEventReasons, or on older drivers its former name
  // nvmlDeviceGetCurrentClocksThrottleReasons (the same call); null when the library has neither.
  nvml::NvmlReturn (*clockReasons)(nvml::NvmlDevice, unsigned long long*) = nullptr;

  ~Nvml() {
    if (initialised) shutdown();
    if (library) dlclose(library);
  }

  template <typename F>
  bool resolve(F& fn, const char* name) {
    fn = reinterpret_cast<F>(dlsym(library, name));
    return fn != nullptr;
  }

  std::string error(nvml::NvmlReturn r) const {
    const char* s = errorString ? errorString(r) : nullptr;
    return s ? s : "NVML error " + std::to_string(r);
  }

  double read(nvml::NvmlReturn (*fn)(nvml::NvmlDevice, nvml::NvmlClockType, unsigned*),
              nvml::NvmlClockType type) const {
    unsigned v = 0;
    return fn(device, type, &v) == nvml::kNvmlSuccess ? double(v) : kNotRead;
  }

  // The device whose UUID, without NVML's "GPU-" prefix, is `vulkanUuid` (case aside); "" on
  // success, else why not.
  std::string findDevice(const std::string& vulkanUuid) {
    const std::string wanted = "GPU-" + vulkanUuid;
    const nvml::NvmlReturn r = handleByUuid(wanted.c_str(), &device);
    if (r == nvml::kNvmlSuccess) return "";
    if (r != nvml::kNvmlErrorNotFound)
      return "nvmlDeviceGetHandleByUUID(" + wanted + ") failed: " + error(r) + ": no telemetry";
    // The same UUID in other letters' case, and the list for the message where there is none.
    unsigned n = 0;
    std::string seen;
    if (count(&n) == nvml::kNvmlSuccess)
      for (unsigned i = 0; i < n; ++i) {
        nvml::NvmlDevice d = nullptr;
        char name[nvml::kNvmlUuidBufferSize] = {};
        if (handleByIndex(i, &d) != nvml::kNvmlSuccess || uuid(d, name, sizeof name) != nvml::kNvmlSuccess) continue;
        if (asciiLower(name) == asciiLower(wanted)) {
          device = d;
          return "";
        }
        seen += std::string(seen.empty() ? "" : ", ") + name;
      }
    device = nullptr;
    return "NVML has no device with UUID " + wanted + " (it has " + (seen.empty() ? "none" : seen) + "): no telemetry";
  }
};

Telemetry::Telemetry(std::string reason)
    : reason_(std::move(reason)), maxSmClockMHz_(kNotRead), maxMemClockMHz_(kNotRead) {}
Telemetry::Telemetry(Telemetry&& other) noexcept = default;
Telemetry& Telemetry::operator=(Telemetry&& other) noexcept = default;
Telemetry::~Telemetry() = default;

Telemetry Telemetry::open(const DeviceInfo& device, const char* library) {
  if (device.vendorId != kNvidiaVendorId)
    return Telemetry("the device is not NVIDIA (vendor " + hexText(device.vendorId) +
                     (device.vendor.empty() ? "" : ", " + device.vendor) + "): no telemetry");
  if (device.uuid.empty()) return Telemetry("the device reports no UUID to find it by in NVML: no telemetry");
  auto nvml = std::make_unique<Nvml>();
  // RTLD_LOCAL: NVML's symbols stay out of the global namespace of the process.
  nvml->library = dlopen(library, RTLD_NOW | RTLD_LOCAL);
  if (!nvml->library) {
    // dlerror: "libnvidia-ml.so.1: cannot open shared object file: ...", said without the name.
    const char* error = dlerror();
    std::string why = error ? error : "";
    if (why.rfind(std::string(library) + ": ", 0) == 0) why.erase(0, std::string(library).size() + 2);
    return Telemetry(std::string("no ") + library + " (NVML, which the NVIDIA driver installs" +
                     (why.empty() ? "" : ": " + why) + "): no telemetry");
  }
  const std::pair<bool, const char*> required[] = {
      {nvml->resolve(nvml->init, "nvmlInit_v2"), "nvmlInit_v2"},
      {nvml->resolve(nvml->shutdown, "nvmlShutdown"), "nvmlShutdown"},
      {nvml->resolve(nvml->errorString, "nvmlErrorString"), "nvmlErrorString"},
      {nvml->resolve(nvml->handleByUuid, "nvmlDeviceGetHandleByUUID"), "nvmlDeviceGetHandleByUUID"},
      {nvml->resolve(nvml->count, "nvmlDeviceGetCount_v2"), "nvmlDeviceGetCount_v2"},
      {nvml->resolve(nvml->handleByIndex, "nvmlDeviceGetHandleByIndex_v2"), "nvmlDeviceGetHandleByIndex_v2"},
      {nvml->resolve(nvml->uuid, "nvmlDeviceGetUUID"), "nvmlDeviceGetUUID"},
      {nvml->resolve(nvml->clock, "nvmlDeviceGetClockInfo"), "nvmlDeviceGetClockInfo"},
      {nvml->resolve(nvml->maxClock, "nvmlDeviceGetMaxClockInfo"), "nvmlDeviceGetMaxClockInfo"},
      {nvml->resolve(nvml->power, "nvmlDeviceGetPowerUsage"), "nvmlDeviceGetPowerUsage"},
      {nvml->resolve(nvml->temperature, "nvmlDeviceGetTemperature"), "nvmlDeviceGetTemperature"},
  };
  for (const auto& [found, name] : required)
    if (!found) return Telemetry(std::string(library) + " has no " + name + " (a driver too old): no telemetry");
  if (!nvml->resolve(nvml->clockReasons, "nvmlDeviceGetCurrentClocksEventReasons"))
    nvml->resolve(nvml->clockReasons, "nvmlDeviceGetCurrentClocksThrottleReasons");
  if (const nvml::NvmlReturn r = nvml->init(); r != nvml::kNvmlSuccess)
    return Telemetry("nvmlInit_v2 failed: " + nvml->error(r) + ": no telemetry");
  nvml->initialised = true;
  if (std::string why = nvml->findDevice(device.uuid); !why.empty()) return Telemetry(std::move(why));

  Telemetry t("");
  t.maxSmClockMHz_ = nvml->read(nvml->maxClock, nvml::kNvmlClockSm);
  t.maxMemClockMHz_ = nvml->read(nvml->maxClock, nvml::kNvmlClockMem);
  char name[nvml::kNvmlUuidBufferSize] = {};
  t.nvmlUuid_ = nvml->uuid(nvml->device, name, sizeof name) == nvml::kNvmlSuccess ? name : "GPU-" + device.uuid;
  t.nvml_ = std::move(nvml);
  return t;
}

std::optional<TelemetrySample> Telemetry::sample() const {
  if (!nvml_) return std::nullopt;
  const Nvml& n = *nvml_;
  TelemetrySample s;
  s.smClockMHz = n.read(n.clock, nvml::kNvmlClockSm);
  s.memClockMHz = n.read(n.clock, nvml::kNvmlClockMem);
  unsigned v = 0;
  s.powerW = n.power(n.device, &v) == nvml::kNvmlSuccess ? v * 1e-3 : kNotRead;  // NVML reports milliwatts
  s.temperatureC = n.temperature(n.device, nvml::kNvmlTemperatureGpu, &v) == nvml::kNvmlSuccess ? double(v) : kNotRead;
  unsigned long long reasons = 0;
  s.throttleReasonsRead = n.clockReasons && n.clockReasons(n.device, &reasons) == nvml::kNvmlSuccess;
  s.throttleReasons = s.throttleReasonsRead ? uint64_t(reasons) : 0;
  s.throttleNames = clockReasonNames(s.throttleReasons);
  return s;
}

json Telemetry::deviceJson() const {
  if (!nvml_) return unavailableTelemetryJson(reason_);
  return {{"available", true},
          {"source", "NVML (libnvidia-ml.so.1), matched by UUID"},
          {"nvml_uuid", nvmlUuid_},
          {"max_sm_clock_mhz", numberOrNull(maxSmClockMHz_)},
          {"max_memory_clock_mhz", numberOrNull(maxMemClockMHz_)}};
}

json Telemetry::measurementJson(const std::optional<TelemetrySample>& before,
                                const std::optional<TelemetrySample>& after) const {
  if (!nvml_) return unavailableTelemetryJson(reason_);
  if (!before || !after) return unavailableTelemetryJson("no reading before or after the measurement");
  return toJson(*before, *after);
}

}  // namespace hb
