#include "config/config_overrides.h"

#include <filesystem>

#include "base/errors.h"
#include "base/input_file.h"
#include "base/json_reader.h"
#include "plan/effects.h"
#include "scene/environment.h"

namespace hb {

using OrderedJson = nlohmann::ordered_json;

namespace {

// Sets key in every named variant's params that has it; refused when they differ (the config
// sweeps it) or when a grid axis sweeps it.
void setEverywhere(OrderedJson& doc, const std::string& key, const OrderedJson& value, const std::string& flag) {
  if (doc.contains("grid") && doc["grid"].is_object() && doc["grid"].contains(key))
    throw InputError(flag + ": the config sweeps " + key + " (its \"grid\" has it); leave out " + flag +
                     " or write a config without that axis");
  if (doc.contains("variants") && doc["variants"].is_array()) {
    std::optional<OrderedJson> seen;
    for (OrderedJson& v : doc["variants"]) {
      if (!v.is_object() || !v.contains("params") || !v["params"].is_object() || !v["params"].contains(key)) continue;
      if (seen && *seen != v["params"][key])
        throw InputError(flag + ": the config's variants differ in " + key + " (they sweep it); leave out " + flag +
                         " or write a config whose variants share it");
      seen = v["params"][key];
      v["params"][key] = value;
    }
  }
  if (!doc.contains("defaults") || !doc["defaults"].is_object()) doc["defaults"] = OrderedJson::object();
  doc["defaults"][key] = value;
  if (key == "resolution") doc.erase("resolution");  // the top-level shorthand; one of the two may stay
}

// Lays the --set over the config's effects and over each variant's own value for that effect
// (both lie below --set): a key the --set leaves out keeps theirs (layerEffectValue).
void setEffect(OrderedJson& doc, const std::string& set) {
  const EffectsLayer layer = parseEffectSet(set);  // checks it: "--set shadows=maybe: ..."
  for (auto it = layer.object.begin(); it != layer.object.end(); ++it) {
    const std::string effect = it.key();  // named: clang cannot capture structured bindings
    const nlohmann::json value = it.value();
    auto layerOver = [&](OrderedJson& effects) {
      const nlohmann::json below = effects.contains(effect) ? nlohmann::json(effects[effect]) : nlohmann::json();
      effects[effect] = OrderedJson(layerEffectValue(below, value));
    };
    if (!doc.contains("effects") || !doc["effects"].is_object()) doc["effects"] = OrderedJson::object();
    layerOver(doc["effects"]);
    auto inParams = [&](OrderedJson& params) {
      if (params.is_object() && params.contains("effects") && params["effects"].is_object() &&
          params["effects"].contains(effect))
        layerOver(params["effects"]);
    };
    if (doc.contains("defaults")) inParams(doc["defaults"]);
    if (doc.contains("variants") && doc["variants"].is_array())
      for (OrderedJson& v : doc["variants"])
        if (v.is_object() && v.contains("params")) inParams(v["params"]);
  }
}

}  // namespace

Environment environmentOfSet(const std::string& set, OrderedJson* asJson) {
  const std::string text = set.substr(set.find('=') + 1);
  OrderedJson value = OrderedJson::parse(text, nullptr, /*allow_exceptions=*/false);
  if (value.is_discarded() || value.is_string()) value = OrderedJson{{"image", text}};
  if (value.is_array()) value = OrderedJson{{"color", value}};
  if (!value.is_object())
    throw InputError("--set " + set +
                     ": give an .hdr image path, a colour [r, g, b] or {\"image\": ..., \"color\": ..., "
                     "\"intensity\": ..., \"rotation\": ...}");
  if (value.contains("image") && value["image"].is_string())
    value["image"] = std::filesystem::absolute(value["image"].get<std::string>()).lexically_normal().string();
  Environment e = readEnvironment(value, json_reader::Where{"--set " + set, ""}, std::filesystem::current_path());
  if (asJson) *asJson = value;
  return e;
}

Config loadConfigWith(const std::string& path, const ConfigOverrides& o) {
  const std::string source = path.empty() ? "thesis.json (embedded)" : path;
  const std::string text = path.empty()
                               ? std::string(embeddedDefaultConfigText())
                               : readInputText(path, "give the path of a config JSON file (e.g. configs/thesis.json)");
  OrderedJson doc = json_reader::parseText(text, source);
  if (!o.any()) return parseConfig(doc, source);
  if (!doc.is_object()) return parseConfig(doc, source);  // the parser says what is wrong

  if (!o.scene.empty()) {
    std::filesystem::path p(o.scene);
    const bool file = p.has_extension() && (p.extension() == ".gltf" || p.extension() == ".glb" ||
                                            p.extension() == ".GLTF" || p.extension() == ".GLB");
    doc["scene"] = file && p.is_relative() ? std::filesystem::absolute(p).lexically_normal().string() : o.scene;
    if (o.scene != "atrium") doc.erase("scene_params");
  }
  if (o.resolution)
    setEverywhere(doc, "resolution", OrderedJson::array({(*o.resolution)[0], (*o.resolution)[1]}), "--size");
  for (const std::string& set : o.sets) {
    const std::string flag = "--set " + set;
    if (isEffectSet(set)) {
      setEffect(doc, set);
      continue;
    }
    if (set.rfind("environment=", 0) == 0) {
      environmentOfSet(set, &doc["environment"]);
      continue;
    }
    if (set.rfind("camera=", 0) == 0) {
      if (set != "camera=auto")
        throw InputError(flag +
                         ": the only camera setting is camera=auto (a camera framing the scene's bounds); "
                         "pick another of the scene's cameras with a config's \"camera\": {\"index\": N}");
      doc["camera"] = "auto";
      continue;
    }
    VariantParams probe;
    applySetOverride(probe, set);  // checks key and value: one line naming the --set
    const std::string key = set.substr(0, set.find('='));
    setEverywhere(doc, key, OrderedJson(toJson(probe)[key]), flag);
  }
  return parseConfig(doc, source + " (with command-line changes)");
}

}  // namespace hb
