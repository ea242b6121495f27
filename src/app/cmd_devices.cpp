#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "base/errors.h"
#include "gpu/vk_context.h"

namespace hb {

nlohmann::json deviceJson(const DeviceInfo& d) {
  return {{"index", d.index},
          {"name", d.name},
          {"type", d.type},
          {"vendor", d.vendor},
          {"vendor_id", d.vendorId},
          {"device_id", d.deviceId},
          {"driver", d.driverName},
          {"driver_info", d.driverInfo},
          {"driver_version", d.driverVersion},
          {"api_version", d.apiVersion},
          {"uuid", d.uuid},
          {"acceleration_structure", d.accelerationStructure},
          {"ray_query", d.rayQuery},
          {"pipeline_statistics", d.pipelineStatistics},
          {"ray_tracing_pipeline", d.rayTracingPipeline},
          {"rt_backends", d.rtBackends()},
          {"timestamps", d.timestamps},
          {"timestamp_valid_bits", d.timestampValidBits},
          {"timestamp_period_ns", d.timestampPeriodNs}};
}

int cmdDevices(bool json) {
  std::vector<DeviceInfo> devices = enumerateDevices();
  if (json) {
    nlohmann::json arr = nlohmann::json::array();
    for (const auto& d : devices) arr.push_back(deviceJson(d));
    std::cout << nlohmann::json{{"devices", arr}}.dump(2) << "\n";
    return kExitOk;
  }
  if (devices.empty()) std::printf("no Vulkan devices\n");
  for (const auto& d : devices) {
    std::printf("%u: %s\n", d.index, d.name.c_str());
    std::printf("   type %s, vendor %s (0x%04x), driver %s %s (%s), Vulkan %s\n", d.type.c_str(), d.vendor.c_str(),
                d.vendorId, d.driverName.c_str(), d.driverVersion.c_str(), d.driverInfo.c_str(), d.apiVersion.c_str());
    std::printf(
        "   acceleration structures: %s, ray query: %s, ray-tracing pipeline: %s, timestamps: %s (%u bits, %.3g "
        "ns/tick)\n",
        d.accelerationStructure ? "yes" : "no", d.rayQuery ? "yes" : "no", d.rayTracingPipeline ? "yes" : "no",
        d.timestamps ? "yes" : "no", d.timestampValidBits, d.timestampPeriodNs);
    if (!d.rayQuery && !d.rayTracingPipeline)
      std::printf("   this device cannot trace rays: usable for raster-only work (shadows off)\n");
  }
  return kExitOk;
}

}  // namespace hb
