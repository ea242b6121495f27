// Anti-aliasing (3D rasterization paper, Fig. 8) regenerated from a results file: per run with an
// "aa" parameter, its frame and primary-visibility times against the same variant without AA (the
// run whose params differ only in "aa", which is "none"), the paper's factors beside them (16x
// MSAA 11x the time of no AA, CSAA 4 + 12 4.3x; the paper's frame shades every sample by ray
// tracing, ours once per pixel and distinct triangle), the sample planes' sub-pass, the shading
// pass, the image error against the run's reference (reference_ssaa 64: the same frame supersampled
// 64 times) and the sample planes' coverage against exact rasterization at the sample positions.
// Empty when no run has an aa other than "none".
#pragma once
#include <string>

#include <nlohmann/json.hpp>

namespace hb {

std::string aaTableMarkdown(const nlohmann::json& results);

}  // namespace hb
