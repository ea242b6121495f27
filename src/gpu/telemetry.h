// An NVIDIA device's clocks, power, temperature and why its clocks are held down, read through NVML
// (docs/usage.md "Telemetry"), so that a results file says whether its times ran at the device's
// steady speed. NVML is loaded at run time (dlopen of libnvidia-ml.so.1, which the NVIDIA driver
// installs): the tool neither links nor needs it, and on any other device, or without the driver,
// telemetry is unavailable and says why, and nothing fails.
#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gpu/vk_context.h"

namespace hb {

// NVML's clocks event reasons (nvmlClocksEventReason*, formerly nvmlClocksThrottleReason*: the NVML
// API reference, "NvmlClocksEventReasons"): bits of the mask nvmlDeviceGetCurrentClocksEventReasons
// returns. Several can be set at once.
inline constexpr uint64_t kClockReasonGpuIdle = 0x1;
inline constexpr uint64_t kClockReasonApplicationsClocksSetting = 0x2;
inline constexpr uint64_t kClockReasonSwPowerCap = 0x4;
inline constexpr uint64_t kClockReasonHwSlowdown = 0x8;
inline constexpr uint64_t kClockReasonSyncBoost = 0x10;
inline constexpr uint64_t kClockReasonSwThermalSlowdown = 0x20;
inline constexpr uint64_t kClockReasonHwThermalSlowdown = 0x40;
inline constexpr uint64_t kClockReasonHwPowerBrakeSlowdown = 0x80;
inline constexpr uint64_t kClockReasonDisplayClockSetting = 0x100;
// In NVML's current reference, not yet in R550's.
inline constexpr uint64_t kClockReasonBoardLimit = 0x200;
inline constexpr uint64_t kClockReasonReliability = 0x400;

// The reasons that do not make a measurement throttled (see throttlingReasons).
inline constexpr uint64_t kBenignClockReasons = kClockReasonGpuIdle | kClockReasonApplicationsClocksSetting |
                                                kClockReasonSyncBoost | kClockReasonDisplayClockSetting;

// The names of the bits set in `mask`, lowest bit first: "gpu_idle", "applications_clocks_setting",
// "sw_power_cap", "hw_slowdown", "sync_boost", "sw_thermal_slowdown", "hw_thermal_slowdown",
// "hw_power_brake_slowdown", "display_clock_setting", "board_limit", "reliability"; a bit NVML has
// not documented is "bit_0x800" (its value).
std::vector<std::string> clockReasonNames(uint64_t mask);

// The bits of `mask` that mean the clocks were throttled: every bit but kBenignClockReasons.
uint64_t throttlingReasons(uint64_t mask);

// One reading of the device. A figure NVML could not read is NaN (null in JSON).
struct TelemetrySample {
  double smClockMHz = 0, memClockMHz = 0;
  double powerW = 0;  // the board's, NVML's milliwatts / 1000 (averaged over 1 s on Ampere and later)
  double temperatureC = 0;
  bool throttleReasonsRead = false;        // false: NVML could not read them (throttleReasons is then 0)
  uint64_t throttleReasons = 0;            // the clocks event reasons mask at the time of the reading
  std::vector<std::string> throttleNames;  // clockReasonNames(throttleReasons)
};

// Whether a measurement between two readings ran throttled: whether either reading carries a
// reason of throttlingReasons. A reading sees the reasons of its instant only: a slowdown that came
// and went between the two is not seen (their clocks may still show it).
bool throttled(const TelemetrySample& before, const TelemetrySample& after);

// {"sm_clock_mhz", "memory_clock_mhz", "power_w", "temperature_c", "clock_reasons_mask",
// "clock_reasons"}; a figure not read is null, and so are both reasons fields when not read.
nlohmann::json toJson(const TelemetrySample& s);
// Around one measurement: {"available": true, "before", "after", "throttled", "throttle_reasons"
// (the names of the throttling reasons of either reading)}, and "warning" (throttleWarning) when
// throttled. "throttled" is null (not known) when a reading could not read its reasons and no
// reading that could shows throttling.
nlohmann::json toJson(const TelemetrySample& before, const TelemetrySample& after);
// {"available": false, "reason": reason}
nlohmann::json unavailableTelemetryJson(const std::string& reason);
// The line a throttled measurement carries in its warnings; empty when it did not throttle.
std::string throttleWarning(const TelemetrySample& before, const TelemetrySample& after);

inline constexpr const char* kNvmlLibrary = "libnvidia-ml.so.1";

// NVML opened for one Vulkan device, matched by UUID (DeviceInfo::uuid is NVML's without its "GPU-"
// prefix: the driver reports the same UUID to both). Owns the library and NVML's initialisation:
// the destructor shuts NVML down and closes the library. NVML is thread-safe and counts its
// initialisations, so each device's sweep may hold its own.
class Telemetry {
 public:
  // Never throws. Where NVML cannot be used (not an NVIDIA device, no driver, no such UUID, NVML
  // failing) the result is unavailable and reason() says why in one line. `library`: what to
  // dlopen (tests name one that does not exist).
  static Telemetry open(const DeviceInfo& device, const char* library = kNvmlLibrary);

  Telemetry(Telemetry&& other) noexcept;
  Telemetry& operator=(Telemetry&& other) noexcept;
  Telemetry(const Telemetry&) = delete;
  Telemetry& operator=(const Telemetry&) = delete;
  ~Telemetry();

  bool available() const { return nvml_ != nullptr; }
  const std::string& reason() const { return reason_; }  // why not available; "" when available
  // A reading now; empty when unavailable.
  std::optional<TelemetrySample> sample() const;
  // The device's highest SM and memory clocks (nvmlDeviceGetMaxClockInfo), MHz; NaN where not read
  // or unavailable.
  double maxSmClockMHz() const { return maxSmClockMHz_; }
  double maxMemClockMHz() const { return maxMemClockMHz_; }

  // context.device.telemetry: {"available": true, "source", "nvml_uuid", "max_sm_clock_mhz",
  // "max_memory_clock_mhz"} or {"available": false, "reason"}.
  nlohmann::json deviceJson() const;
  // A measurement's telemetry from the readings before and after it: toJson(before, after), or
  // {"available": false, "reason"} when either reading is missing.
  nlohmann::json measurementJson(const std::optional<TelemetrySample>& before,
                                 const std::optional<TelemetrySample>& after) const;

 private:
  struct Nvml;  // the loaded library, its entry points, its initialisation and the device
  explicit Telemetry(std::string reason);
  std::unique_ptr<Nvml> nvml_;  // null: unavailable
  std::string reason_;
  std::string nvmlUuid_;  // NVML's name of the device, "GPU-..."
  double maxSmClockMHz_, maxMemClockMHz_;
};

}  // namespace hb
