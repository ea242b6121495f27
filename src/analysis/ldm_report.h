// The layered depth maps' memory and lists as render.json reports them (ambient occlusion and
// indirect light): maps, heads, nodes allocated and used, nodes per map pixel, the exact need.
#pragma once
#include <cstdint>

#include <nlohmann/json.hpp>

#include "frame/passes/ldm_build.h"

namespace hb {

// linkBytes: the list storage as allocated. Reads the build's counters (after an analysis frame).
nlohmann::json ldmJson(const LdmBuild& ldm, uint64_t linkBytes);

}  // namespace hb
