// Helpers for FramePass::work (frame/frame_pass.h): a figure of the analysis frame's record by its
// path, and the work items every pass declares in the same words.
#pragma once
#include <initializer_list>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "frame/frame_pass.h"
#include "shared/gpu_types.h"

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

// The work of a layered-depth-map build (frame/passes/ldm_build.h) and of each of its steps
// (LdmBuild::subPasses: ".insert", or sbuffer's ".count", ".scan", ".fill", ".sort"), from the record
// of the effect that built it ("ambient_occlusion" or "indirect": its "ldm" counters, "ldm_build"
// and "ldm_list"). A geometry step of the 3dr build does, per (triangle, map) pair, the view of its
// three vertices (3 x 16 operations: a subtraction, 3 dot products, the pixel mapping) and, per
// pixel of a listed chunk (ldm.chunks x 512), three edge values and the owner tests (about 20); the
// small pairs' own pixels are not counted, so the fma figure is a lower bound.
inline std::vector<PassWork> ldmBuildWork(const std::string& pass, const nlohmann::json& effect,
                                          double sceneTriangles) {
  const double maps = figureAt(effect, {"ldm", "maps"});
  const double fragments = figureAt(effect, {"ldm", "fragments"});
  const double heads = figureAt(effect, {"ldm", "heads"});
  const double chunks = figureAt(effect, {"ldm", "chunks"});
  const bool hardware = effect.value("ldm_build", "") == "hardware";
  const bool sbuffer = effect.value("ldm_list", "") == "sbuffer";
  auto geometry = [&](std::vector<WorkItem> items) {
    if (hardware) {
      items.push_back(derived("triangles", sceneTriangles * maps, "every scene triangle drawn into every map"));
      items.push_back(counted("fragments", fragments, "LDM fragments (ldm.fragments)"));
    } else {
      items.push_back(derived("fma", sceneTriangles * maps * 48 + chunks * gpu::kLdmChunk * 20,
                              "48 operations per (triangle, map) pair's view + 20 per pixel of a listed chunk "
                              "(ldm.chunks x 512); a lower bound"));
    }
    return items;
  };
  if (!sbuffer) {
    const double bytes = 8 * figureAt(effect, {"ldm", "nodes_used"}) + 4 * heads;
    std::vector<WorkItem> items =
        geometry({counted("atomics", fragments, "one list insertion per LDM fragment (ldm.fragments)"),
                  derived("bytes", bytes, "8 B per list node used + 4 B per head written once")});
    return {{pass, items}, {pass + ".insert", items}};
  }
  // sbuffer: a count atomic and a cursor atomic per fragment; the counts scanned (read twice,
  // written once); each fragment's 8 B written, then read and written by the sort with the offsets.
  const std::string perFragment = "one atomic per LDM fragment (ldm.fragments)";
  std::vector<PassWork> work{
      {pass + ".count", geometry({counted("atomics", fragments, perFragment),
                                  derived("bytes", 4 * heads, "a 4 B count per map pixel")})},
      {pass + ".scan", {derived("bytes", 12 * heads, "each count read twice and its offset written once")}},
      {pass + ".fill", geometry({counted("atomics", fragments, perFragment),
                                 derived("bytes", 8 * fragments + 4 * heads,
                                         "each fragment's depth and triangle id written, a cursor per map pixel")})},
      {pass + ".sort",
       {derived("bytes", 16 * fragments + 8 * heads,
                "each fragment's 8 B read and written once, two offsets per map pixel")}}};
  std::vector<WorkItem> whole =
      geometry({counted("atomics", 2 * fragments, "a count and a cursor atomic per LDM fragment (ldm.fragments)"),
                derived("bytes", 28 * heads + 24 * fragments, "its steps' bytes together")});
  for (WorkItem& item : whole)  // two geometry passes: count and fill
    if (item.unit != "atomics" && item.unit != "bytes") item.amount *= 2;
  work.insert(work.begin(), PassWork{pass, whole});
  return work;
}

}  // namespace hb
