// Which ray tracer a frame's ray passes use (config "backend"): the driver's (ray query where the
// device has it, else the ray-tracing pipeline) or ours in compute (docs/methods/compute-ray-tracing.md).
// backend=auto keeps the driver's unless the device's own measured rates say ours is faster on both
// kinds of ray; the frame records which ran and why (render.json "backend", "backend_choice").
#pragma once
#include <string>

#include <nlohmann/json.hpp>

#include "frame/render_settings.h"
#include "gpu/peaks.h"
#include "gpu/trace_bvh.h"
#include "gpu/vk_context.h"

namespace hb {

struct BackendChoice {
  RtBackend requested = RtBackend::Auto;
  RtBackend ran = RtBackend::RayQuery;  // never Auto
  std::string reason;
};

// The frame's ray tracer: resolved once by the Renderer (chooseBackend) and taken as it is by every
// pass that traces (shadows, raybench, ambient occlusion, the environment light, indirect light,
// primary=raycast), which reads the backend and the handles from it instead of re-encoding the
// choice. The frame's keyed resources own the handles (frame_builder.h).
struct RayTracer {
  BackendChoice choice;  // which ran (never Auto) and why
  // The driver's scene: built whenever the frame traces, also with backend=compute (an analysis
  // frame's references trace through it; raybench compares the backends).
  VkAccelerationStructureKHR tlas = VK_NULL_HANDLE;
  const TraceBvh* bvh = nullptr;  // backend=compute: our BVH (nodes, triangles, width, stack); else null

  RtBackend backend() const { return choice.ran; }
  bool compute() const { return choice.ran == RtBackend::Compute; }
  bool rayQuery() const { return choice.ran == RtBackend::RayQuery; }  // else the pipeline (or compute)
};

// Ours must beat the driver's by this factor on both ray kinds for auto to take it: above the
// run-to-run spread of the peaks' ray rates (their repetitions vary by under 3 % on the H200) with
// room, so that two runs of one device do not choose differently.
inline constexpr double kAutoComputeMargin = 1.10;

// The rates auto chooses from, out of the peaks measured on the frame's scene (addRayPeaks): the
// random occlusion and closest-hit rays through our BVH of `bvhWidth` and through the driver's
// tracer (ray query where the device has it); empty where either was not measured.
std::optional<RayRates> rayRatesOf(const Peaks& peaks, const DeviceInfo& device, uint32_t bvhWidth = 4);

BackendChoice chooseBackend(RtBackend requested, const DeviceInfo& device, const std::optional<RayRates>& rates);
nlohmann::json toJson(const BackendChoice& choice, const std::optional<RayRates>& rates);

}  // namespace hb
