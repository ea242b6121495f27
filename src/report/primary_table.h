// The 3D rasterization continuum (Davidovic et al. 2012, Section 5) regenerated from a results
// file: per run, its primary-visibility method, that pass's GPU time against the hardware depth
// prepass, the whole frame, and what the method did in the analysis frame (triangle setups,
// pixels tested, edge evaluations and atomics per pixel, fp64 fallbacks) with the paper's
// instruction estimate (the record's paper_scalar_ops_estimate, Fig. 10: 57 scalar operations per
// 3DR setup and 12 per pixel tested, 73 and 14 for 2DR; results without it get 57 and 12). As in the
// paper's Fig. 9, time and estimate are also given relative to 2DR brute force: the run whose
// primary method is "2dr" with this run's r3d_thread_box, else the first "2dr" run ("—", and a note
// in the caption, when there is none). The counters of the BVH methods (nodes visited, frusta,
// culled triangles and early-z blocks) get three columns, left out when no run has them.
// Empty unless some run's primary visibility is not the hardware prepass (a compute method or a ray
// cast): a sweep of the prepass alone has nothing to set beside it.
#pragma once
#include <string>

#include <nlohmann/json.hpp>

namespace hb {

// Scalar operations of 3D rasterization in the paper's Fig. 10 (setup, per pixel evaluated).
constexpr double kPaper3drSetupOps = 57.0;
constexpr double kPaper3drPixelOps = 12.0;

std::string primaryTableMarkdown(const nlohmann::json& results);

}  // namespace hb
