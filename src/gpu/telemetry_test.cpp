// NVML telemetry (gpu/telemetry.h): which clocks event reasons make a measurement throttled, their
// names, the JSON a run carries, and opening it where NVML cannot be used (another vendor, no
// library, a UUID NVML does not know), which must give a reason and never throw.
#include "gpu/telemetry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "base/errors.h"

namespace hb {
namespace {

using nlohmann::json;

TelemetrySample sampleWith(uint64_t reasons, double smClockMHz = 1980) {
  TelemetrySample s;
  s.smClockMHz = smClockMHz;
  s.memClockMHz = 2619;
  s.powerW = 412.5;
  s.temperatureC = 61;
  s.throttleReasonsRead = true;
  s.throttleReasons = reasons;
  s.throttleNames = clockReasonNames(reasons);
  return s;
}

bool throttledAlone(uint64_t reasons) { return throttled(sampleWith(reasons), sampleWith(0)); }

TEST(Telemetry, OnlyPowerHeatAndHardwareSlowdownsCountAsThrottling) {
  EXPECT_FALSE(throttledAlone(0));
  // Idle at the instant of the reading, or clocks fixed by a setting: the same in every run.
  for (uint64_t benign : {kClockReasonGpuIdle, kClockReasonApplicationsClocksSetting, kClockReasonSyncBoost,
                          kClockReasonDisplayClockSetting}) {
    SCOPED_TRACE(benign);
    EXPECT_FALSE(throttledAlone(benign));
    EXPECT_EQ(throttlingReasons(benign), 0u);
  }
  EXPECT_FALSE(throttledAlone(kBenignClockReasons));
  for (uint64_t slowdown :
       {kClockReasonSwPowerCap, kClockReasonHwSlowdown, kClockReasonSwThermalSlowdown, kClockReasonHwThermalSlowdown,
        kClockReasonHwPowerBrakeSlowdown, kClockReasonBoardLimit, kClockReasonReliability}) {
    SCOPED_TRACE(slowdown);
    EXPECT_TRUE(throttledAlone(slowdown));
    // Beside benign reasons it still counts, and only it is named.
    EXPECT_EQ(throttlingReasons(slowdown | kBenignClockReasons), slowdown);
  }
  // A bit NVML documents later counts until it is known to be harmless.
  EXPECT_TRUE(throttledAlone(0x800));
}

TEST(Telemetry, EitherReadingThrottledMakesTheMeasurementThrottled) {
  EXPECT_TRUE(throttled(sampleWith(kClockReasonSwPowerCap), sampleWith(kClockReasonGpuIdle)));
  EXPECT_TRUE(throttled(sampleWith(0), sampleWith(kClockReasonHwThermalSlowdown)));
  EXPECT_FALSE(throttled(sampleWith(kClockReasonGpuIdle), sampleWith(kClockReasonApplicationsClocksSetting)));
}

TEST(Telemetry, NamesEveryDocumentedBitLowestFirstAndOthersByValue) {
  EXPECT_EQ(
      clockReasonNames(0x7FF),
      (std::vector<std::string>{"gpu_idle", "applications_clocks_setting", "sw_power_cap", "hw_slowdown", "sync_boost",
                                "sw_thermal_slowdown", "hw_thermal_slowdown", "hw_power_brake_slowdown",
                                "display_clock_setting", "board_limit", "reliability"}));
  EXPECT_EQ(clockReasonNames(0), std::vector<std::string>{});
  EXPECT_EQ(clockReasonNames(kClockReasonHwThermalSlowdown | kClockReasonSwPowerCap),
            (std::vector<std::string>{"sw_power_cap", "hw_thermal_slowdown"}));
  EXPECT_EQ(clockReasonNames(0x800 | (uint64_t(1) << 63)),
            (std::vector<std::string>{"bit_0x800", "bit_0x8000000000000000"}));
}

TEST(Telemetry, AMeasurementCarriesBothReadingsTheVerdictItsReasonsAndAWarning) {
  const TelemetrySample before = sampleWith(kClockReasonGpuIdle, 1980);
  TelemetrySample after = sampleWith(kClockReasonSwPowerCap | kClockReasonApplicationsClocksSetting, 1755);
  after.powerW = std::numeric_limits<double>::quiet_NaN();  // NVML could not read it
  const json j = toJson(before, after);
  EXPECT_EQ(j["available"], true);
  EXPECT_EQ(j["throttled"], true);
  // The reasons that throttled, not the benign ones beside them.
  EXPECT_EQ(j["throttle_reasons"], json({"sw_power_cap"}));
  for (const char* side : {"before", "after"}) {
    SCOPED_TRACE(side);
    ASSERT_TRUE(j[side].is_object());
    for (const char* key :
         {"sm_clock_mhz", "memory_clock_mhz", "power_w", "temperature_c", "clock_reasons_mask", "clock_reasons"})
      EXPECT_TRUE(j[side].contains(key)) << key;
  }
  EXPECT_EQ(j["before"]["sm_clock_mhz"], 1980.0);
  EXPECT_EQ(j["before"]["power_w"], 412.5);
  EXPECT_EQ(j["before"]["clock_reasons"], json({"gpu_idle"}));
  EXPECT_EQ(j["after"]["clock_reasons_mask"], kClockReasonSwPowerCap | kClockReasonApplicationsClocksSetting);
  EXPECT_EQ(j["after"]["clock_reasons"], json({"applications_clocks_setting", "sw_power_cap"}));
  EXPECT_TRUE(j["after"]["power_w"].is_null()) << j["after"].dump();  // null, not NaN (invalid JSON)
  const std::string warning = j.value("warning", "");
  EXPECT_EQ(warning, throttleWarning(before, after));
  EXPECT_NE(warning.find("sw_power_cap"), std::string::npos) << warning;
  EXPECT_NE(warning.find("1980 MHz before, 1755 MHz after"), std::string::npos) << warning;

  // Not throttled: false, no reasons, no warning.
  const json calm = toJson(sampleWith(0), sampleWith(kClockReasonGpuIdle));
  EXPECT_EQ(calm["throttled"], false);
  EXPECT_EQ(calm["throttle_reasons"], json::array());
  EXPECT_FALSE(calm.contains("warning"));
  EXPECT_EQ(throttleWarning(sampleWith(0), sampleWith(0)), "");
}

TEST(Telemetry, UnreadReasonsLeaveTheVerdictUnknownUnlessAReadingShowsThrottling) {
  TelemetrySample unread = sampleWith(0);
  unread.throttleReasonsRead = false;
  unread.throttleNames.clear();
  const json j = toJson(unread, sampleWith(0));
  EXPECT_TRUE(j["throttled"].is_null()) << j.dump();
  EXPECT_TRUE(j["before"]["clock_reasons"].is_null());
  EXPECT_TRUE(j["before"]["clock_reasons_mask"].is_null());
  EXPECT_EQ(toJson(unread, sampleWith(kClockReasonHwSlowdown))["throttled"], true);
}

TEST(Telemetry, UnavailableIsOneFieldThatSaysWhy) {
  const json j = unavailableTelemetryJson("no libnvidia-ml.so.1");
  EXPECT_EQ(j, json({{"available", false}, {"reason", "no libnvidia-ml.so.1"}}));
}

DeviceInfo testDevice(uint32_t vendorId, const std::string& vendor) {
  DeviceInfo d;
  d.name = vendor + " test device";
  d.vendorId = vendorId;
  d.vendor = vendor;
  d.uuid = "00000000-0000-0000-0000-000000000000";  // no NVIDIA device has it
  return d;
}

void expectUnavailable(const Telemetry& t, const std::string& because) {
  EXPECT_FALSE(t.available());
  EXPECT_NE(t.reason().find(because), std::string::npos) << t.reason();
  EXPECT_FALSE(t.sample().has_value());
  EXPECT_EQ(t.deviceJson(), unavailableTelemetryJson(t.reason()));
  EXPECT_EQ(t.measurementJson(t.sample(), t.sample()), unavailableTelemetryJson(t.reason()));
  EXPECT_TRUE(std::isnan(t.maxSmClockMHz()));
}

TEST(Telemetry, AnotherVendorsDeviceHasNoneAndSaysSoWithoutThrowing) {
  expectUnavailable(Telemetry::open(testDevice(0x10005, "Mesa")), "the device is not NVIDIA (vendor 0x10005, Mesa)");
}

TEST(Telemetry, WithoutTheLibraryThereIsNoneAndTheReasonNamesIt) {
  expectUnavailable(Telemetry::open(testDevice(0x10DE, "NVIDIA"), "libhybridbench-no-such-nvml.so.1"),
                    "no libhybridbench-no-such-nvml.so.1");
}

TEST(Telemetry, AnNvidiaUuidNvmlDoesNotKnowGivesNoneAndAReasonOnAnyMachine) {
  // Here without an NVIDIA driver: no library. With one: NVML has no device of that UUID.
  const Telemetry t = Telemetry::open(testDevice(0x10DE, "NVIDIA"));
  EXPECT_FALSE(t.available());
  EXPECT_NE(t.reason(), "");
  EXPECT_NE(t.reason().find("no telemetry"), std::string::npos) << t.reason();
}

TEST(Telemetry, EveryDeviceOfThisMachineOpensWithoutThrowingAndReadsWhereAvailable) {
  std::vector<DeviceInfo> devices;
  try {
    devices = enumerateDevices();
  } catch (const DeviceError& e) {
    GTEST_SKIP() << "no Vulkan here: " << e.what();
  }
  for (const DeviceInfo& d : devices) {
    SCOPED_TRACE(d.name);
    const Telemetry t = Telemetry::open(d);
    if (d.vendorId != 0x10DE) {
      expectUnavailable(t, "not NVIDIA");  // lavapipe, another vendor's GPU
      continue;
    }
    if (!t.available()) {  // an NVIDIA device where NVML cannot be used (a container without it)
      EXPECT_NE(t.reason(), "");
      continue;
    }
    EXPECT_EQ(t.reason(), "");
    EXPECT_EQ(t.deviceJson()["nvml_uuid"], "GPU-" + d.uuid);
    const std::optional<TelemetrySample> s = t.sample();
    ASSERT_TRUE(s.has_value());
    EXPECT_GT(s->smClockMHz, 0);
    EXPECT_LE(s->smClockMHz, t.maxSmClockMHz());
    EXPECT_GT(s->memClockMHz, 0);
    EXPECT_TRUE(std::isnan(s->powerW) || s->powerW > 0) << s->powerW;  // NaN: a board that reports none
    EXPECT_GT(s->temperatureC, 0);
  }
}

}  // namespace
}  // namespace hb
