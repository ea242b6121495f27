// Helpers for FramePass::work (frame/frame_pass.h): a figure of the analysis frame's record by its
// path, and the work items every pass declares in the same words.
#pragma once
#include <initializer_list>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "frame/frame_pass.h"

namespace hb {

// The number at analysis[k0][k1]..., or 0 where any key is missing or the value is not a number.
inline double figureAt(const nlohmann::json& analysis, std::initializer_list<const char*> path) {
  const nlohmann::json* j = &analysis;
  for (const char* key : path) {
    if (!j->is_object() || !j->contains(key)) return 0;
    j = &(*j)[key];
  }
  return j->is_number() ? j->get<double>() : 0;
}

inline WorkItem counted(const char* unit, double amount, const std::string& what) {
  return {unit, amount, "counted: " + what};
}
inline WorkItem derived(const char* unit, double amount, const std::string& how) {
  return {unit, amount, "derived: " + how};
}

// The work of a layered-depth-map build (frame/passes/ldm_build.h), from the record of the effect
// that built it ("ambient_occlusion" or "indirect": its "ldm" counters and "ldm_build" method).
inline std::vector<WorkItem> ldmBuildWork(const nlohmann::json& effect, double sceneTriangles) {
  const double maps = figureAt(effect, {"ldm", "maps"});
  const double fragments = figureAt(effect, {"ldm", "fragments"});
  const double bytes = 8 * figureAt(effect, {"ldm", "nodes_used"}) + 4 * figureAt(effect, {"ldm", "heads"});
  std::vector<WorkItem> items = {counted("atomics", fragments, "one list insertion per LDM fragment (ldm.fragments)"),
                                 derived("bytes", bytes, "8 B per list node used + 4 B per head written once")};
  if (effect.value("ldm_build", "") == "hardware") {
    items.push_back(derived("triangles", sceneTriangles * maps, "every scene triangle drawn into every map"));
    items.push_back(counted("fragments", fragments, "LDM fragments (ldm.fragments)"));
  }
  return items;
}

}  // namespace hb
