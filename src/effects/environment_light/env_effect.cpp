#include "effects/environment_light/env_effect.h"

#include "effects/environment_light/env_part.h"

namespace hb {

namespace {

constexpr const char* kEnvironmentMethods[] = {"ldm", "raytraced", "reference"};

AoSettings readEnvironmentLight(const nlohmann::ordered_json& value, const json_reader::Where& where) {
  using namespace json_reader;
  AoSettings s;
  if (!validateEffectValue(environmentLightEffect(), value, where)) return s;
  static constexpr AoMethod kAoMethods[] = {AoMethod::Ldm, AoMethod::RayTraced, AoMethod::Reference};
  if (value.contains("method"))
    s.method = kAoMethods[readChoice(value["method"], where.key("method"),
                                     {kEnvironmentMethods[0], kEnvironmentMethods[1], kEnvironmentMethods[2]})];
  readLdmSettings(value, where, s);
  readSquareSamples(value, where, s.samples);
  return s;
}

void validateEnvironmentLight(const nlohmann::ordered_json& value, const json_reader::Where& where) {
  readEnvironmentLight(value, where);
}

std::vector<FrameResource> environmentNeedsOf(const nlohmann::json& value) {
  if (environmentSettingsOf(value).method == AoMethod::Ldm)
    return {FrameResource::Depth, FrameResource::LayeredDepthMaps};
  return {FrameResource::Depth, FrameResource::AccelerationStructures};
}

std::vector<const char*> environmentPassesOf(const nlohmann::json& value) {
  if (environmentSettingsOf(value).method == AoMethod::Ldm) return {kEnvironmentLdmBuildPass, kEnvironmentLightPass};
  return {kEnvironmentLightPass};
}

std::string environmentCannotAct(const Scene& scene, const nlohmann::json& /*value*/) {
  if (!scene.environment)
    return "the scene has no environment (add extras.environment to the glTF scene or \"environment\" to the "
           "config)";
  if (!(scene.environment->intensity > 0.0f)) return "the environment's intensity is 0";
  return "";
}

}  // namespace

AoSettings environmentSettingsOf(const nlohmann::json& value) {
  return readEnvironmentLight(nlohmann::ordered_json(value), json_reader::Where{"effects", "environment_light"});
}

const EffectDef& environmentLightEffect() {
  static const EffectDef def{
      .name = "environment_light",
      .summary =
          "direct light of the scene's environment (an .hdr or a colour): its visibility along N directions "
          "by layered depth maps, the same directions ray traced, or a Monte Carlo reference",
      .defaultValue = false,
      .validate = validateEnvironmentLight,
      .needs = {FrameResource::Depth},
      .passes = {kEnvironmentLdmBuildPass, kEnvironmentLightPass},
      .cannotAct = environmentCannotAct,
      .needsOf = environmentNeedsOf,
      .passesOf = environmentPassesOf,
      .build = buildEnvironmentLight,
      .report = reportEnvironmentLight,
      .table = environmentTableMarkdown,
      .settings =
          {
              {"method", "ldm | raytraced | reference", "\"ldm\"",
               "layered depth maps along N directions; the same N directions ray traced; cosine-weighted Monte "
               "Carlo (the converged reference); each direction weighted by the environment's radiance"},
              {"directions", "1..2048", "64", "N: the LDM directions (each traced both ways)"},
              kLdmResolutionSetting,
              kLdmBiasSetting,
              kLdmListSetting,
              kLdmBuildSetting,
              {"samples", "a square in 16..65536", "1024", "reference rays per pixel (side x side strata)"},
          },
  };
  return def;
}

}  // namespace hb
