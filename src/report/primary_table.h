// The 3D rasterization continuum (Davidovic et al. 2012, Section 5) regenerated from a results
// file: per run, its primary-visibility method, that pass's GPU time against the hardware depth
// prepass, the whole frame, and what the method did in the analysis frame (triangle setups,
// pixels tested, edge evaluations and atomics per pixel, fp64 fallbacks) with the paper's
// instruction estimate (Fig. 10: 57 scalar operations per 3DR setup, 12 per pixel tested).
// Empty when no run carries a "primary" block (results from before primary visibility methods).
#pragma once
#include <string>

#include <nlohmann/json.hpp>

namespace hb {

// Scalar operations of 3D rasterization in the paper's Fig. 10 (setup, per pixel evaluated).
constexpr double kPaper3drSetupOps = 57.0;
constexpr double kPaper3drPixelOps = 12.0;

std::string primaryTableMarkdown(const nlohmann::json& results);

}  // namespace hb
