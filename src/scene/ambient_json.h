// The ambient term's JSON form, shared by a glTF scene's extras.ambient and a config's "ambient":
// {"color": [r, g, b] (each >= 0, default [1, 1, 1]), "intensity": x (>= 0)}.
#pragma once
#include <nlohmann/json.hpp>

#include "base/json_reader.h"
#include "scene/scene.h"

namespace hb {

// Throws InputError naming where and the fix.
Ambient readAmbient(const nlohmann::ordered_json& value, const json_reader::Where& where);
nlohmann::json toJson(const Ambient& a);

}  // namespace hb
