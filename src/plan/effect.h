// An effect: something a scene calls for (shadows, ambient occlusion, indirect light, ...),
// declared once with its schema, what it needs from the frame, the passes it adds and the hooks
// that build, report and tabulate it (docs/frame.md "Effects", docs/contributing.md "Adding an
// effect or a pass"). An effect lives in one folder, src/effects/<name>/, and is listed once in
// src/effects/builtin/builtin_effects.cpp; a test registers its own with registerEffect (effects.h).
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "base/json_reader.h"
#include "scene/scene.h"

namespace hb {

class FramePart;
class Renderer;
struct FrameBuilder;
struct EffectReport;
struct ReferenceFrame;

// What a pass needs that is allocated only when some pass of the frame needs it.
enum class FrameResource : uint32_t {
  Depth,                   // the primary-visibility depth buffer
  LightLists,              // per-tile light lists (tile frustums + light culling)
  AccelerationStructures,  // BLAS per mesh + TLAS
  LayeredDepthMaps,        // the LDMs' maps, lists and node pool (ambient occlusion by LDM)
};
const char* toString(FrameResource r);

// Where an effect's passes go in the frame: after the light lists and before shading (the
// effects that shading composes), or after shading (effects on the shaded image).
enum class FramePhase : uint32_t { BeforeShading, AfterShading };

// One setting of an effect's object form ({"method": "ldm", "directions": 64}): the validator
// accepts exactly these keys (validateEffectValue), and `hybridbench help effects` prints them.
struct EffectSetting {
  const char* name;
  const char* accepts;       // what the validator accepts: "ldm | raytraced | reference", "1..2048"
  const char* defaultValue;  // as JSON: "64", "\"ldm\"", "null"
  const char* description;
};

struct EffectDef {
  const char* name;     // the key in "effects" / "extras.effects", render.json and results.json
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
  // Settings that no layer gave but that another setting decides (indirect: bounces > 1 with method
  // ldm need ldm_list "sbuffer"), filled in once the layers are merged. `given(key)` is the origin
  // of a setting some layer gave ("" when none did): a choice the user made is never overridden;
  // where it conflicts this throws InputError naming the setting, its origin and the fix. Returns
  // the completed value and appends one line per choice to `notes`. Null: nothing to complete.
  // Precondition: value passed validate.
  nlohmann::json (*complete)(const nlohmann::json& value, const std::function<std::string(const char*)>& given,
                             std::vector<std::string>& notes) = nullptr;

  FramePhase phase = FramePhase::BeforeShading;
  // Builds the effect's GPU state and passes for the frame (frame/frame_builder.h): the passes
  // of the plan it runs, each declaring what it reads and writes; publishes what later parts read.
  // Throws InputError when the settings cannot run on this frame or device.
  std::unique_ptr<FramePart> (*build)(FrameBuilder& frame) = nullptr;
  // After an analysis frame: writes report.run[name] (render.json and each results.json run),
  // its images, its summary lines and its accuracy figures (analysis/effect_report.h).
  void (*report)(EffectReport& report) = nullptr;
  // After an analysis frame of the reference parameters (analysis/render_outputs.h
  // captureReference): keeps what the effect's accuracy is measured against.
  void (*captureReference)(const Renderer& renderer, ReferenceFrame& reference) = nullptr;
  // Its table from a results file, Markdown ("" when the file has no rows for it): `sweep`
  // writes it into tables.md and `tables` prints it.
  std::string (*table)(const nlohmann::json& results) = nullptr;
  // Its settings when its value may be an object; empty: true or false only.
  std::vector<EffectSetting> settings = {};
};

// The shape every effect value has: true, false, or an object of `def.settings` (unknown keys get a
// did-you-mean). Returns true for an object, whose settings the effect then reads; throws
// InputError naming where.prefix() and the fix.
bool validateEffectValue(const EffectDef& def, const nlohmann::ordered_json& value, const json_reader::Where& where);

// An effect's value asks for it unless it is false (true, or an object of its settings).
inline bool isCalledFor(const nlohmann::json& value) { return !(value.is_boolean() && !value.get<bool>()); }

}  // namespace hb
