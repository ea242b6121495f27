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
  if (value.contains("directions"))
    s.directions = uint32_t(readInt(value["directions"], where.key("directions"), 1, 2048));
  if (value.contains("ldm_resolution"))
    s.ldmResolution = uint32_t(readInt(value["ldm_resolution"], where.key("ldm_resolution"), 8, 4096));
  if (value.contains("bias")) s.bias = readNumber(value["bias"], where.key("bias"), 0.0, 1e6, true);
  readLdmListAndBuild(value, where, s.ldmList, s.ldmBuild);
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
              {"ldm_resolution", "8..4096", "128", "R: each map is R x R over the scene's bounding sphere"},
              {"bias", "a number > 0", "1", "scale of the derived slope-scaled LDM bias"},
              kLdmListSetting,
              kLdmBuildSetting,
              {"samples", "a square in 16..65536", "1024", "reference rays per pixel (side x side strata)"},
          },
  };
  return def;
}

}  // namespace hb
