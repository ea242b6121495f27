// The device's own ceilings (`hybridbench peaks`, docs/usage.md "peaks"): microbenchmarks of
// memory bandwidth, atomics, FP32 FMA and the hardware rasterizer, each the median of repeated
// timed dispatches. A pass's roofline (report/roofline.h) divides what it achieved by these.
//
// Timing: GPU timestamps around each repetition on a GPU; on a CPU device (lavapipe, whose
// timestamps do not bracket compute work) the host's clock around the submission, which includes
// the submission itself: the figures are small but real.
#pragma once
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gpu/vk_context.h"
#include "reference/ray_file.h"
#include "scene/scene.h"

namespace hb {

struct Peak {
  std::string key;          // "memory_read", "atomic_add_distinct", ...
  std::string unit;         // what is counted: "bytes", "atomics", "fma", "triangles", "fragments"
  double perSecond = 0;     // median rate
  double work = 0;          // units per repetition
  std::vector<double> ms;   // each repetition's time
  std::string description;  // what one repetition does, in words
  std::string backend;  // ray figures: the tracer, pipeline | rayquery | compute[-w4|-w8][-persistent] ("" otherwise)
  double missed = -1;   // ray figures: the rays that met nothing (-1 otherwise), equal across backends
  nlohmann::json compiled;  // ray files, compute backends: vk_pipeline.h pipelineStatistics (null: not offered)
};

struct Peaks {
  std::vector<Peak> figures;
  std::string timing;  // "gpu timestamps" or "host clock (CPU device)"
  // What makes the figures doubtful (addRayPeaks: the device's speed changed while they ran).
  std::vector<std::string> warnings;
  nlohmann::json warmUp;  // how the device was warmed before the figures (gpu/warm_up.h toJson); null: not
  // The rate for a unit a pass counts (report/roofline.cpp): bytes -> the highest of read, write
  // and copy; atomics -> distinct 32-bit adds; atomics64 -> atomicMin on 64 bits; fma; triangles;
  // fragments; rays_coherent, rays_random, rays_occlusion, rays_ao (addRayPeaks), through
  // `backend` where given and measured (else the first backend measured). 0 where nothing measured it.
  double rateFor(const std::string& unit, const std::string& backend = "") const;
};

// Measures every figure on ctx's device (a few seconds on a GPU, about a second on lavapipe), after
// warming it until steady (gpu/warm_up.h; a device that never settled adds a warning).
// Figures the device cannot run (64-bit atomics) are left out.
Peaks measurePeaks(const VulkanContext& ctx);

// Adds the device's ray rates on `scene`, the same rays through every backend the device has (our
// BVH in compute, the ray-tracing pipeline, ray query; keys rays_camera, rays_camera_compute,
// rays_camera_rayquery, ...; a device that cannot trace adds none): camera rays of a full-HD image
// (rays_coherent), random rays in the scene's bounds to the closest hit (rays_random) and as
// occlusion rays (rays_occlusion), and AO rays from the surfaces the camera sees (rays_ao). They
// depend on the scene, so they are never cached; a sweep adds them for its scene.
// everyBackend false: the driver's backends only (a CPU device's render and sweep, where the
// timings mean nothing and each figure costs a second; `peaks` measures them all).
void addRayPeaks(const VulkanContext& ctx, const Scene& scene, Peaks& peaks, bool everyBackend = true);

// The three ray sets of the public compute tracers' figures (reference/ray_sets.h, as `rays export`
// makes them from the scene's first camera at the ray peaks' size: camera rays, AO rays of 1 m and
// shadow rays to a point light at (0, 6, 0) from each camera hit, all closest hit), made on the CPU
// and traced by every backend: keys rays_public_camera, rays_public_ao, rays_public_shadow with the
// backend's suffix, units of the same names. `hybridbench peaks` adds them; a sweep does not.
void addPublicRayPeaks(const VulkanContext& ctx, const Scene& scene, Peaks& peaks);

// A ray file (reference/ray_file.h) traced by every backend the device has: our BVH at each width
// (and persistent), the driver's ray-tracing pipeline and ray query. Per backend one figure (key
// "rays_file_<backend>", unit "rays_file": the rays of the file a second) and what each ray found:
// missed (1) or not (0), and for a closest-hit file the hit's t (-1: missed; the pipeline runs no hit
// shader and gives none). The launch is the file's grid, 8x8 rays a group. Precondition: the device
// can trace, the file is of this scene (the caller checks its sha256).
struct RayFileHits {
  std::vector<float> t;          // -1: missed; empty where the backend gives none (the pipeline)
  std::vector<uint32_t> missed;  // 1: missed
  std::vector<uint32_t> ids;  // closest hits through our BVH or ray query: the triangle's draw-order id (~0u: missed)
};
struct RayFileTrace {
  std::vector<Peak> figures;
  std::map<std::string, RayFileHits> hits;  // by backend name
  std::vector<std::string> warnings;
};
RayFileTrace traceRayFile(const VulkanContext& ctx, const Scene& scene, const RayFile& file);

// {"version", "timing", "figures": {key: {unit, per_s, work, ms: {median, min, max, samples}, description}}}
nlohmann::json toJson(const Peaks& peaks, const DeviceInfo& device);
Peaks peaksFromJson(const nlohmann::json& j);

// The peaks of ctx's device from the cache, keyed by device UUID and driver version (and the
// microbenchmarks' version); measured and cached when absent. The cache folder is
// HYBRIDBENCH_PEAKS_CACHE, else $XDG_CACHE_HOME/hybridbench/peaks, else ~/.cache/hybridbench/peaks;
// a cache that cannot be written is skipped (the figures are still returned). *fromCache says which.
Peaks cachedPeaks(const VulkanContext& ctx, bool* fromCache = nullptr);
std::string peaksCachePath(const DeviceInfo& device);

// "2.91 TB/s", "61.2 G fma/s", "1.05 G triangles/s": a rate in the unit a peak or pass counts.
std::string formatRate(double perSecond, const std::string& unit);

}  // namespace hb
