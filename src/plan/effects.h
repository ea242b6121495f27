// The effects a scene calls for, and the frame they make (docs/frame.md "Effects").
//
// One schema, used as a config's "effects" and as a glTF scene's "extras.effects":
//   {"shadows": true|false, "ambient_occlusion": ..., "indirect": ...}   (hybridbench help effects)
// Precedence, lowest first: the built-in default < the scene's extras < the config < --set.
// An effect called for that cannot act on the scene (no light casts shadows) is skipped with that
// reason. The frame is the list of passes in frame order that the base frame (primary
// visibility, light lists for direct light, shading) and the effects that run need; nothing an
// effect needs is allocated when it does not run.
#pragma once
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "base/json_reader.h"
#include "plan/effect.h"
#include "scene/scene.h"

namespace hb {

// Every effect, in the order reports list them: the built-in ones (builtinEffects), then those
// registered.
const std::vector<const EffectDef*>& allEffects();
const EffectDef* findEffect(std::string_view name);  // nullptr if none is called that
// The effects of src/effects/<name>/, listed once in src/effects/builtin/builtin_effects.cpp.
std::vector<const EffectDef*> builtinEffects();
// Adds an effect defined elsewhere (a test's own, say) after the others; `def` outlives every use.
// Precondition: its name and its passes' names are new.
void registerEffect(const EffectDef& def);
// Removes an effect registerEffect added (a test's clean-up); built-in effects stay.
void unregisterEffect(const EffectDef& def);

// The base frame's passes: primary visibility (one of three methods), the light lists, shading.
inline constexpr const char* kDepthPrepassPass = "depth_prepass";
inline constexpr const char* kRaster3dPass = "raster3d";
inline constexpr const char* kRayCastPass = "raycast";
inline constexpr const char* kLightCullingPass = "light_culling";
inline constexpr const char* kShadingPass = "shading";

// Every pass the frame can run, in frame order: primary visibility, light culling, the
// passes of the effects that come before shading (in effect order), shading, then the passes of
// the effects after shading.
std::vector<std::string> framePassOrder();
// The passes of the base frame, which no effect adds.
bool isBaseFramePass(std::string_view pass);

enum class EffectSource { Default, Scene, Config, Set };
const char* toString(EffectSource source);

// Checks an effects object: an object whose keys are effects and whose values each effect accepts.
// Throws InputError "<where.source>: <where.path>.<key>: ..." (unknown keys get a did-you-mean).
void validateEffects(const nlohmann::ordered_json& object, const json_reader::Where& where);
void validateEffects(const nlohmann::json& object, const json_reader::Where& where);

// One source's effects object (already validated) and where it came from (a file, "--set ...").
struct EffectsLayer {
  EffectSource source = EffectSource::Config;
  std::string origin;
  nlohmann::json object = nlohmann::json::object();
};

// What is asked for above the scene: the config's layer, then each --set, lowest first.
struct EffectsRequest {
  std::vector<EffectsLayer> layers;
  // Appends a layer (validated here; throws InputError naming origin).
  EffectsRequest& add(EffectSource source, std::string origin, const nlohmann::json& object);
};

// "--set shadows=false" and "--set effects.shadows=false" name an effect; "tile_size=8" does not.
bool isEffectSet(const std::string& keyEqualsValue);
// Parses such an argument into a Set layer (the value is JSON, e.g. false or {"method": "ldm"}).
// Throws InputError naming the argument.
EffectsLayer parseEffectSet(const std::string& keyEqualsValue);

// One effect's value `above` laid over the value `below` it (docs/usage.md "Precedence"): a key
// the higher layer leaves out keeps the value of the layer below.
//   above false          -> false (off; the settings below are dropped)
//   above true           -> below when below is an object (on, with its settings), else true
//   above an object      -> below's settings (when below is an object) with above's keys on top
// Precondition: both values passed the effect's validator.
nlohmann::json layerEffectValue(const nlohmann::json& below, const nlohmann::json& above);

struct EffectState {
  std::string name;
  nlohmann::json value;  // as called for, after precedence
  EffectSource source = EffectSource::Default;
  std::string origin;  // the file or argument that decided it ("" for the default)
  // Where each setting of an object value came from (its layer's origin, or "chosen by the tool").
  std::map<std::string, std::string> settingOrigins;
  // What the tool chose for settings no layer gave (EffectDef::complete), one line each.
  std::vector<std::string> notes;
  bool calledFor = false;
  bool runs = false;
  std::string skippedBecause;  // why it does not run ("" when it runs)
};

struct FramePlan {
  std::vector<EffectState> effects;                          // in allEffects() order
  std::vector<std::string> passes;                           // that run, in frame order
  std::vector<std::pair<std::string, std::string>> skipped;  // passes not run, with the reason
  std::vector<FrameResource> resources;                      // allocated for the frame

  bool runs(std::string_view effect) const;
  bool hasPass(std::string_view pass) const;
  bool needs(FrameResource r) const;
  // {"shadows": {"called_for": true, "runs": false, "source": "scene", "origin": "x.gltf",
  //  "value": true, "skipped_because": "no light casts shadows"}, ...}; an object value adds
  //  "settings_from": {setting: origin}, a tool's choice adds "notes": [...]
  nlohmann::json effectsJson() const;
};

// The effects of a scene under a request, and the frame they make. scene.effects (the glTF's
// extras.effects, validated by the loader) is the Scene layer.
// primaryPass: the pass that computes primary visibility (kDepthPrepassPass, kRaster3dPass or
// kRayCastPass; ray casting needs the acceleration structures).
FramePlan planFrame(const Scene& scene, const EffectsRequest& request,
                    const std::string& primaryPass = kDepthPrepassPass);

}  // namespace hb
