// An effect: something a scene calls for (shadows today; ambient occlusion and indirect light
// next), declared once with its schema, what it needs from the frame and which passes it adds
// (design.md "Effects"). The frame is assembled from the effects that run (effects.h), so a new
// effect is one pair of files like shadows.{h,cpp} plus one line in allEffects().
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "base/json_reader.h"
#include "scene/scene.h"

namespace hb {

// What a pass needs that is allocated only when some pass of the frame needs it.
enum class FrameResource : uint32_t {
  Depth,                   // the primary-visibility depth buffer
  LightLists,              // per-tile light lists (tile frustums + light culling)
  AccelerationStructures,  // BLAS per mesh + TLAS
  LayeredDepthMaps,        // the LDMs' maps, lists and node pool (ambient occlusion by LDM)
};
const char* toString(FrameResource r);

struct EffectDef {
  const char* name;     // the key in "effects" / "extras.effects"
  const char* summary;  // one line: what it simulates and how
  // Its value when nothing asks otherwise (built-in default).
  nlohmann::json defaultValue;
  // Checks a value given for this effect; throws InputError naming where.prefix() and the fix.
  // Precondition: none (any JSON value may arrive here from a file).
  void (*validate)(const nlohmann::ordered_json& value, const json_reader::Where& where);
  std::vector<FrameResource> needs;
  std::vector<const char*> passes;  // the passes it adds, in frame order
  // Why the effect cannot act on this scene although it is called for ("" when it can), e.g.
  // "no light casts shadows". Precondition: value passed validate.
  std::string (*cannotAct)(const Scene& scene, const nlohmann::json& value);
  // Where what it needs and adds depends on its value (a method, say): those of this value, a
  // subset of `needs` ∪ {LayeredDepthMaps, AccelerationStructures} and of `passes`. Null: the
  // static lists. A pass of `passes` that a value does not add is listed as skipped.
  std::vector<FrameResource> (*needsOf)(const nlohmann::json& value) = nullptr;
  std::vector<const char*> (*passesOf)(const nlohmann::json& value) = nullptr;
};

// An effect's value asks for it unless it is false (true, or an object of its settings).
inline bool isCalledFor(const nlohmann::json& value) { return !(value.is_boolean() && !value.get<bool>()); }

}  // namespace hb
