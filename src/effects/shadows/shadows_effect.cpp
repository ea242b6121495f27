#include "effects/shadows/shadows_effect.h"

#include <algorithm>

#include "effects/shadows/shadows_part.h"
#include "report/tables.h"

namespace hb {

static void validateShadows(const nlohmann::ordered_json& value, const json_reader::Where& where) {
  json_reader::readBool(value, where);
}

static std::string shadowsCannotAct(const Scene& scene, const nlohmann::json& /*value*/) {
  if (scene.lights.empty()) return "the scene has no lights";
  if (std::none_of(scene.lights.begin(), scene.lights.end(), [](const Light& l) { return l.castShadows; }))
    return "no light casts shadows";
  // The shadow pass traces the lights of each pixel's tile list; directional lights are never
  // culled into tile lists (light_culling is skipped when every light is directional).
  if (std::all_of(scene.lights.begin(), scene.lights.end(),
                  [](const Light& l) { return l.type == LightType::Directional; }))
    return "every light is directional: not supported by the tiled shadow pass yet";
  return "";
}

const EffectDef& shadowsEffect() {
  static const EffectDef def{
      .name = "shadows",
      .summary = "ray-traced hard shadows, one ray per (pixel, light of its tile) that N·L does not cull",
      .defaultValue = true,
      .validate = validateShadows,
      .needs = {FrameResource::Depth, FrameResource::LightLists, FrameResource::AccelerationStructures},
      .passes = {kShadowsPass},
      .cannotAct = shadowsCannotAct,
      .build = buildShadows,
      .report = reportShadows,
      .captureReference = captureShadowsReference,
  };
  return def;
}

}  // namespace hb
