// What made a result: tool and revision, host, device and driver, scene, and what its times cannot
// be used for. results.json (sweep) and render.json (render) carry it as "context"
// (docs/results-format.md).
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "config/config.h"
#include "gpu/vk_context.h"
#include "scene/scene.h"

namespace hb {

// context: tool {name, version, git}, host, device (deviceJson), scene {name, sha256, triangles,
// lights, camera_source, lights_source}, timing_source, and timing_caveat on a CPU device.
nlohmann::json runContext(const VulkanContext& ctx, const Scene& scene);

// What identifies a sweep's inputs, beside runContext's (docs/results-format.md#identity):
// config (toJson of the effective config), config_file (configFile made absolute; absent when
// empty: the embedded default), overrides.set (the sweep's --set arguments as given, in order;
// absent without any: `history` keeps runs of other overrides in series of their own), and
// scene.environment_sha256 (the config's environment image, as loaded: its size and texels) where
// the config names one. Merged into a context with update().
nlohmann::json inputsContext(const Config& config, const std::string& configFile,
                             const std::vector<std::string>& sets = {});

// The caveat a CPU device's times carry (lavapipe: per-pass times mean nothing).
extern const char* const kCpuTimingCaveat;

// Frame median minus the sum of the passes' medians (barriers, gaps between passes); sub-pass
// entries ("raster3d.tiles") lie inside their pass and are not added again.
double frameMinusPassesMs(double frameMs, const std::vector<std::pair<std::string, double>>& passMs);

}  // namespace hb
