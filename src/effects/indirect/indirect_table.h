// Single-bounce indirect light (Aalund et al. 2015, Sect. 5.2) regenerated from a results file.
#pragma once
#include <string>

#include <nlohmann/json.hpp>

namespace hb {

// Single-bounce indirect light (Sect. 5.2): per run its method, directions, map size and photons,
// the LDM build, photon tracing and splatting passes' GPU times, the frame, the split photons
// (slots, stored, discarded share), memory, and the irradiance's errors (relative MSE, total
// light ratio, FLIP) against the same photons ray traced and the gathered reference; then the
// paper's photon-tracing time. Empty when no run carries an "indirect" block.
std::string indirectTableMarkdown(const nlohmann::json& results);

}  // namespace hb
