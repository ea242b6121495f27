#include "plan/effects.h"

#include <algorithm>

#include "base/errors.h"

namespace hb {

static std::vector<const EffectDef*>& effectRegistry() {
  static std::vector<const EffectDef*> effects = builtinEffects();
  return effects;
}

const std::vector<const EffectDef*>& allEffects() { return effectRegistry(); }

void registerEffect(const EffectDef& def) {
  HB_ASSERT(findEffect(def.name) == nullptr);
  for (const char* pass : def.passes) {
    const std::vector<std::string> order = framePassOrder();
    HB_ASSERT(std::find(order.begin(), order.end(), pass) == order.end());
  }
  effectRegistry().push_back(&def);
}

void unregisterEffect(const EffectDef& def) {
  const std::vector<const EffectDef*> builtin = builtinEffects();
  HB_ASSERT(std::find(builtin.begin(), builtin.end(), &def) == builtin.end());
  auto& r = effectRegistry();
  r.erase(std::remove(r.begin(), r.end(), &def), r.end());
}

const EffectDef* findEffect(std::string_view name) {
  for (const EffectDef* e : allEffects())
    if (name == e->name) return e;
  return nullptr;
}

constexpr const char* kPrimaryPasses[] = {kDepthPrepassPass, kRaster3dPass, kRayCastPass};

bool isBaseFramePass(std::string_view pass) {
  return std::find(std::begin(kPrimaryPasses), std::end(kPrimaryPasses), pass) != std::end(kPrimaryPasses) ||
         pass == kLightCullingPass || pass == kShadingPass;
}

std::vector<std::string> framePassOrder() {
  std::vector<std::string> order(std::begin(kPrimaryPasses), std::end(kPrimaryPasses));
  order.push_back(kLightCullingPass);
  for (FramePhase phase : {FramePhase::BeforeShading, FramePhase::AfterShading}) {
    if (phase == FramePhase::AfterShading) order.push_back(kShadingPass);
    for (const EffectDef* e : allEffects())
      if (e->phase == phase) order.insert(order.end(), e->passes.begin(), e->passes.end());
  }
  return order;
}

const char* toString(FrameResource r) {
  switch (r) {
    case FrameResource::Depth: return "depth";
    case FrameResource::LightLists: return "light_lists";
    case FrameResource::AccelerationStructures: return "acceleration_structures";
    case FrameResource::LayeredDepthMaps: return "layered_depth_maps";
  }
  return "?";
}

const char* toString(EffectSource source) {
  switch (source) {
    case EffectSource::Default: return "default";
    case EffectSource::Scene: return "scene";
    case EffectSource::Config: return "config";
    case EffectSource::Set: return "--set";
  }
  return "?";
}

bool validateEffectValue(const EffectDef& def, const nlohmann::ordered_json& value, const json_reader::Where& where) {
  if (value.is_boolean()) return false;
  std::vector<std::string_view> names;
  std::string list;
  for (const EffectSetting& s : def.settings) {
    names.push_back(s.name);
    list += (list.empty() ? "" : ", ") + std::string(s.name);
  }
  if (names.empty()) json_reader::readBool(value, where);  // names what it expects
  if (!value.is_object())
    where.fail("expected true, false or an object of settings (" + list + "), got " + json_reader::describe(value));
  json_reader::requireObjectWithKeys(value, where, names);
  return true;
}

static std::vector<std::string_view> effectNames() {
  std::vector<std::string_view> names;
  for (const EffectDef* e : allEffects()) names.push_back(e->name);
  return names;
}

void validateEffects(const nlohmann::ordered_json& object, const json_reader::Where& where) {
  json_reader::requireObjectWithKeys(object, where, effectNames());
  for (const auto& [key, value] : object.items()) findEffect(key)->validate(value, where.key(key));
}

void validateEffects(const nlohmann::json& object, const json_reader::Where& where) {
  validateEffects(nlohmann::ordered_json(object), where);
}

EffectsRequest& EffectsRequest::add(EffectSource source, std::string origin, const nlohmann::json& object) {
  validateEffects(object, {origin, ""});
  layers.push_back({source, std::move(origin), object});
  return *this;
}

static std::string effectKeyOf(const std::string& keyEqualsValue) {
  const size_t eq = keyEqualsValue.find('=');
  std::string key = keyEqualsValue.substr(0, eq);
  if (key.rfind("effects.", 0) == 0) key = key.substr(8);
  return key;
}

bool isEffectSet(const std::string& keyEqualsValue) {
  if (keyEqualsValue.rfind("effects.", 0) == 0) return true;  // an unknown effect fails in parseEffectSet
  return findEffect(effectKeyOf(keyEqualsValue)) != nullptr;
}

EffectsLayer parseEffectSet(const std::string& keyEqualsValue) {
  const std::string where = "--set " + keyEqualsValue;
  const size_t eq = keyEqualsValue.find('=');
  if (eq == std::string::npos) throw InputError(where + ": expected effect=value, e.g. --set shadows=false");
  const std::string key = effectKeyOf(keyEqualsValue);
  const std::string text = keyEqualsValue.substr(eq + 1);
  nlohmann::ordered_json value = nlohmann::ordered_json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (value.is_discarded()) value = text;  // a bare word: the effect's validator names what it wants
  nlohmann::ordered_json object = {{key, value}};
  json_reader::Where w{where, "effects"};
  validateEffects(object, w);
  return {EffectSource::Set, where, nlohmann::json(object)};
}

nlohmann::json layerEffectValue(const nlohmann::json& below, const nlohmann::json& above) {
  if (above.is_boolean()) return above.get<bool>() && below.is_object() ? below : above;
  if (!above.is_object() || !below.is_object()) return above;
  nlohmann::json merged = below;
  for (auto it = above.begin(); it != above.end(); ++it) merged[it.key()] = it.value();
  return merged;
}

bool FramePlan::runs(std::string_view effect) const {
  return std::any_of(effects.begin(), effects.end(), [&](const EffectState& e) { return e.name == effect && e.runs; });
}

bool FramePlan::hasPass(std::string_view pass) const {
  return std::find(passes.begin(), passes.end(), pass) != passes.end();
}

bool FramePlan::needs(FrameResource r) const {
  return std::find(resources.begin(), resources.end(), r) != resources.end();
}

nlohmann::json FramePlan::effectsJson() const {
  nlohmann::json j = nlohmann::json::object();
  for (const EffectState& e : effects) {
    nlohmann::json s = {
        {"called_for", e.calledFor}, {"runs", e.runs}, {"value", e.value}, {"source", toString(e.source)}};
    if (!e.origin.empty()) s["origin"] = e.origin;
    if (e.value.is_object() && !e.settingOrigins.empty()) s["settings_from"] = e.settingOrigins;
    if (!e.notes.empty()) s["notes"] = e.notes;
    if (!e.skippedBecause.empty()) s["skipped_because"] = e.skippedBecause;
    j[e.name] = s;
  }
  return j;
}

FramePlan planFrame(const Scene& scene, const EffectsRequest& request, const std::string& primaryPass) {
  std::vector<EffectsLayer> layers;
  if (!scene.effects.is_null()) layers.push_back({EffectSource::Scene, scene.effectsOrigin, scene.effects});
  layers.insert(layers.end(), request.layers.begin(), request.layers.end());

  FramePlan plan;
  auto addResource = [&](FrameResource r) {
    if (!plan.needs(r)) plan.resources.push_back(r);
  };
  std::vector<std::pair<std::string, std::string>> effectPassSkipped;
  std::vector<std::string> effectPasses;
  for (const EffectDef* def : allEffects()) {
    EffectState s;
    s.name = def->name;
    s.value = def->defaultValue;
    for (const EffectsLayer& layer : layers) {
      if (!layer.object.contains(def->name)) continue;
      const nlohmann::json& above = layer.object[def->name];
      s.value = layerEffectValue(s.value, above);
      if (above.is_object())
        for (const auto& [key, v] : above.items()) s.settingOrigins[key] = layer.origin;
      else if (!s.value.is_object())
        s.settingOrigins.clear();  // false (or true over no settings): what was below is gone
      s.source = layer.source;
      s.origin = layer.origin;
    }
    if (def->complete && s.value.is_object()) {
      auto given = [&](const char* key) {
        auto it = s.settingOrigins.find(key);
        return it == s.settingOrigins.end() ? std::string() : it->second;
      };
      const nlohmann::json before = s.value;
      s.value = def->complete(s.value, given, s.notes);
      for (const auto& [key, v] : s.value.items())
        if (!before.contains(key)) s.settingOrigins[key] = "chosen by the tool";
    }
    s.calledFor = isCalledFor(s.value);
    if (!s.calledFor) {
      s.skippedBecause = std::string("effects.") + def->name + " is off (" + toString(s.source) +
                         (s.origin.empty() ? "" : ": " + s.origin) + ")";
    } else {
      s.skippedBecause = def->cannotAct(scene, s.value);
    }
    s.runs = s.calledFor && s.skippedBecause.empty();
    const std::vector<const char*> used = s.runs && def->passesOf ? def->passesOf(s.value) : def->passes;
    for (const char* pass : def->passes) {
      const bool usedByValue = std::find(used.begin(), used.end(), pass) != used.end();
      if (s.runs && usedByValue)
        effectPasses.push_back(pass);
      else if (s.runs)
        effectPassSkipped.push_back(
            {pass, std::string("effects.") + def->name + " = " + s.value.dump() + " does not use it"});
      else
        effectPassSkipped.push_back({pass, s.skippedBecause});
    }
    if (s.runs)
      for (FrameResource r : def->needsOf ? def->needsOf(s.value) : def->needs) addResource(r);
    plan.effects.push_back(std::move(s));
  }

  // The base frame: primary visibility and shading always; tile light lists for direct light
  // when some light can be culled into tiles (a directional light reaches every pixel).
  addResource(FrameResource::Depth);
  if (primaryPass == kRayCastPass) addResource(FrameResource::AccelerationStructures);
  const bool anyLocalLight = std::any_of(scene.lights.begin(), scene.lights.end(),
                                         [](const Light& l) { return l.type != LightType::Directional; });
  if (anyLocalLight) addResource(FrameResource::LightLists);

  for (const std::string& p : framePassOrder()) {
    const bool byEffect = std::find(effectPasses.begin(), effectPasses.end(), p) != effectPasses.end();
    if (std::find(std::begin(kPrimaryPasses), std::end(kPrimaryPasses), p) != std::end(kPrimaryPasses)) {
      if (p == primaryPass) plan.passes.push_back(p);  // the other methods are not "skipped": not asked for
    } else if (p == kShadingPass || byEffect) {
      plan.passes.push_back(p);
    } else if (p == kLightCullingPass) {
      if (plan.needs(FrameResource::LightLists))
        plan.passes.push_back(p);
      else
        plan.skipped.push_back(
            {p, scene.lights.empty() ? "the scene has no lights" : "every light is directional (never culled)"});
    } else {
      for (const auto& [skippedPass, why] : effectPassSkipped)
        if (skippedPass == p) plan.skipped.push_back({p, why});
    }
  }
  return plan;
}

}  // namespace hb
