#include "frame/ray_backend.h"

#include <string>

#include "base/text_format.h"

namespace hb {

std::optional<RayRates> rayRatesOf(const Peaks& peaks, const DeviceInfo& device, uint32_t bvhWidth) {
  RayRates r;
  r.driver = device.rayQuery ? "rayquery" : "pipeline";
  auto rate = [&](const char* unit, const std::string& backend) {
    for (const Peak& p : peaks.figures)
      if (p.unit == unit && p.backend == backend) return p.perSecond;
    return 0.0;
  };
  const std::string ours = bvhWidth == 2 ? "compute" : "compute-w" + std::to_string(bvhWidth);
  r.driverOcclusion = rate("rays_occlusion", r.driver);
  r.computeOcclusion = rate("rays_occlusion", ours);
  r.driverClosest = rate("rays_random", r.driver);
  r.computeClosest = rate("rays_random", ours);
  if (r.driverOcclusion <= 0 || r.computeOcclusion <= 0 || r.driverClosest <= 0 || r.computeClosest <= 0)
    return std::nullopt;
  r.source = "peaks: rays_random_occlusion and rays_random_closest, " + r.driver + " and " + ours + ", on this scene";
  return r;
}

BackendChoice chooseBackend(RtBackend requested, const DeviceInfo& device, const std::optional<RayRates>& rates) {
  BackendChoice c;
  c.requested = requested;
  const RtBackend driver = device.rayQuery ? RtBackend::RayQuery : RtBackend::Pipeline;
  if (requested != RtBackend::Auto) {
    c.ran = requested;
    c.reason = "set by the config";
    return c;
  }
  c.ran = driver;
  if (device.type == "cpu") {
    c.reason = "auto: the driver's (a CPU device's timings do not bracket its ray work, so no rate decides)";
    return c;
  }
  if (!rates || rates->driverOcclusion <= 0 || rates->computeOcclusion <= 0 || rates->driverClosest <= 0 ||
      rates->computeClosest <= 0) {
    c.reason = "auto: the driver's (no ray rates measured on this device)";
    return c;
  }
  const double any = rates->computeOcclusion / rates->driverOcclusion;
  const double closest = rates->computeClosest / rates->driverClosest;
  const std::string figures = format("compute/%s %.2fx on occlusion rays, %.2fx on closest-hit rays (%s)",
                                     rates->driver.c_str(), any, closest, rates->source.c_str());
  if (any >= kAutoComputeMargin && closest >= kAutoComputeMargin) {
    c.ran = RtBackend::Compute;
    c.reason = "auto: compute, " + figures;
  } else {
    c.reason = format("auto: the driver's, compute is not %.2fx faster on both: ", kAutoComputeMargin) + figures;
  }
  return c;
}

nlohmann::json toJson(const BackendChoice& choice, const std::optional<RayRates>& rates) {
  nlohmann::json j = {
      {"requested", toString(choice.requested)}, {"ran", toString(choice.ran)}, {"reason", choice.reason}};
  if (rates)
    j["rates"] = {{"driver", rates->driver},
                  {"driver_occlusion_per_s", rates->driverOcclusion},
                  {"compute_occlusion_per_s", rates->computeOcclusion},
                  {"driver_closest_per_s", rates->driverClosest},
                  {"compute_closest_per_s", rates->computeClosest},
                  {"source", rates->source}};
  return j;
}

}  // namespace hb
