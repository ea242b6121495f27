// Issue #17's scaling study regenerated from a results file (configs/many-lights*.json): per run its
// light lists (tile: the thesis's, capped at 32 | bitmask | zbin), light count and image, the lights
// per tile, the list memory, the culling, shadow and shading passes' GPU times and the frame, the
// rays traced against the oracle's pairs (efficiency), the pairs dropped by a capped list, and the
// shadow pass's ray rate. Then, per uncapped list form, the least-squares fit of frame time against
// oracle pairs (slope, intercept, R²): the cost of a frame should be its rays, not its bookkeeping.
// Empty when no run uses an uncapped list (light_lists bitmask or zbin).
#pragma once
#include <string>

#include <nlohmann/json.hpp>

namespace hb {

std::string manyLightsTableMarkdown(const nlohmann::json& results);

// The least-squares line y = intercept + slope·x and its R² (1 − residual / total sum of squares;
// 1 when every y is equal and fitted exactly). Precondition: x.size() == y.size() >= 2.
struct LinearFit {
  double slope = 0, intercept = 0, r2 = 0;
};
LinearFit fitLine(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace hb
