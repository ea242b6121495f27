// Ambient occlusion by layered depth maps (Aalund et al. 2015, Sect. 5.1) regenerated from a
// results file: per run its AO method, directions and map size, the LDM build and AO passes' GPU
// times, the whole frame, the LDM memory (allocated, and the exact need: a head per map pixel and a
// node per fragment), nodes per map pixel, and the AO's errors against the same directions ray
// traced and against the Monte Carlo reference; then the paper's own figures beside ours.
// Empty when no run carries an "ambient_occlusion" block.
#pragma once
#include <string>

#include <nlohmann/json.hpp>

namespace hb {

std::string aoTableMarkdown(const nlohmann::json& results);

}  // namespace hb
