// A config changed from the command line (sweep --scene, --size, --set): the changes are made to
// the config's JSON before it is parsed, so the parser checks the result as it checks any file and
// results.json records the effective config. Each --set is checked first, on its own, so a bad
// value is named as "--set key=value".
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "config/config.h"
#include "scene/scene.h"

namespace hb {

struct ConfigOverrides {
  std::string scene;                                  // built-in name or .gltf/.glb path ("": the config's)
  std::optional<std::array<uint32_t, 2>> resolution;  // --size
  std::vector<std::string> sets;                      // --set key=value, in order
  bool any() const { return !scene.empty() || resolution || !sets.empty(); }
};

// The config at path (empty: the embedded thesis.json) with the overrides applied:
// - --set of a parameter sets it in "defaults" and in every named variant; refused (InputError)
//   when the config sweeps that parameter (a "grid" axis, or named variants that differ in it);
// - --set of an effect (shadows=false, ambient_occlusion={"samples":8}, effects.X=...) is laid over
//   the config's "effects" and over every variant's own (layerEffectValue: the keys it leaves out
//   keep theirs);
// - --set camera=auto frames the scene's bounds;
// - --set environment=VALUE replaces the config's "environment" (environmentOfSet);
// - --size sets the resolution as --set resolution=WxH;
// - --scene replaces the scene (a relative path is taken from the working directory) and drops
//   scene_params, which apply only to the atrium, when the new scene is not the atrium.
Config loadConfigWith(const std::string& path, const ConfigOverrides& overrides);

// --set environment=VALUE (`set` starts with "environment="): VALUE is an .hdr path, a colour
// [r, g, b] or the environment's JSON object (scene/environment.h); a relative image path is the
// working directory's. Read here, so that a missing image or a bad field is one InputError naming
// the --set. *asJson, when given, receives the config form (its image path absolute).
Environment environmentOfSet(const std::string& set, nlohmann::ordered_json* asJson = nullptr);

}  // namespace hb
