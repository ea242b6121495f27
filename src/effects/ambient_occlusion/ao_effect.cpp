#include "effects/ambient_occlusion/ao_effect.h"

#include <cmath>
#include <limits>

#include "effects/ambient_occlusion/ao_part.h"
#include "effects/ambient_occlusion/ao_table.h"

namespace hb {

const char* toString(AoMethod m) {
  switch (m) {
    case AoMethod::Ldm: return "ldm";
    case AoMethod::RayTraced: return "raytraced";
    case AoMethod::Reference: return "reference";
    case AoMethod::Hbao: return "hbao";
    case AoMethod::Gtao: return "gtao";
  }
  return "?";
}

AoSettings aoSettingsOf(const nlohmann::json& value);

namespace {

constexpr const char* kMethods[] = {"ldm", "raytraced", "reference", "hbao", "gtao"};

AoSettings readAo(const nlohmann::ordered_json& value, const json_reader::Where& where) {
  using namespace json_reader;
  AoSettings s;
  if (!validateEffectValue(ambientOcclusionEffect(), value, where))
    return s;  // true, false or an object of its settings
  if (value.contains("method"))
    s.method = AoMethod(readChoice(value["method"], where.key("method"),
                                   {kMethods[0], kMethods[1], kMethods[2], kMethods[3], kMethods[4]}));
  if (value.contains("steps")) s.steps = uint32_t(readInt(value["steps"], where.key("steps"), 1, 1024));
  if (value.contains("d_max") && !value["d_max"].is_null())
    s.dMax = readNumber(value["d_max"], where.key("d_max"), 0.0, std::numeric_limits<double>::infinity(), true);
  readLdmSettings(value, where, s);
  readSquareSamples(value, where, s.samples);
  return s;
}

void validateAo(const nlohmann::ordered_json& value, const json_reader::Where& where) { readAo(value, where); }

std::vector<FrameResource> aoNeedsOf(const nlohmann::json& value) {
  const AoMethod m = aoSettingsOf(value).method;
  if (m == AoMethod::Ldm) return {FrameResource::Depth, FrameResource::LayeredDepthMaps};
  if (m == AoMethod::Hbao || m == AoMethod::Gtao) return {FrameResource::Depth};
  return {FrameResource::Depth, FrameResource::AccelerationStructures};
}

std::vector<const char*> aoPassesOf(const nlohmann::json& value) {
  if (aoSettingsOf(value).method == AoMethod::Ldm) return {kLdmBuildPass, kAmbientOcclusionPass};
  return {kAmbientOcclusionPass};
}

std::string aoCannotAct(const Scene& scene, const nlohmann::json& /*value*/) {
  if (!scene.ambient)
    return "the scene has no ambient term (add extras.ambient to the glTF scene or \"ambient\" to the config)";
  if (!(scene.ambient->intensity > 0.0f)) return "the scene's ambient intensity is 0";
  return "";
}

}  // namespace

void readLdmListAndBuild(const nlohmann::ordered_json& value, const json_reader::Where& where, LdmList& list,
                         LdmBuildMethod& build) {
  using namespace json_reader;
  static constexpr LdmList kLists[] = {LdmList::Max64, LdmList::Cas, LdmList::Sbuffer};
  static constexpr LdmBuildMethod kBuilds[] = {LdmBuildMethod::Hardware, LdmBuildMethod::Raster3d};
  if (value.contains("ldm_list"))
    list = kLists[readChoice(value["ldm_list"], where.key("ldm_list"), {"max64", "cas", "sbuffer"})];
  if (value.contains("ldm_build"))
    build = kBuilds[readChoice(value["ldm_build"], where.key("ldm_build"), {"hardware", "3dr"})];
}

void readSquareSamples(const nlohmann::ordered_json& value, const json_reader::Where& where, uint32_t& samples) {
  if (!value.contains("samples")) return;
  samples = uint32_t(json_reader::readInt(value["samples"], where.key("samples"), 16, 65536));
  const uint32_t side = uint32_t(std::lround(std::sqrt(double(samples))));
  if (side * side != samples)
    where.key("samples").fail(std::to_string(samples) + " is not a square (the strata are side x side); use e.g. 256");
}

AoSettings aoSettingsOf(const nlohmann::json& value) {
  return readAo(nlohmann::ordered_json(value), json_reader::Where{"effects", "ambient_occlusion"});
}

nlohmann::json AoSettings::toJson() const {
  nlohmann::json j = {{"method", hb::toString(method)},
                      {"directions", directions},
                      {"ldm_resolution", ldmResolution},
                      {"d_max", dMax ? nlohmann::json(*dMax) : nlohmann::json()},
                      {"bias", bias},
                      {"ldm_list", hb::toString(ldmList)},
                      {"ldm_build", hb::toString(ldmBuild)}};
  if (method == AoMethod::Reference) j["samples"] = samples;
  if (method == AoMethod::Hbao || method == AoMethod::Gtao) j["steps"] = steps;
  return j;
}

const EffectSetting kLdmResolutionSetting{"ldm_resolution", "8..4096", "128",
                                          "R: each map is R x R over the scene's bounding sphere"};
const EffectSetting kLdmBiasSetting{"bias", "a number > 0", "1", "scale of the derived slope-scaled LDM bias"};
const EffectSetting kLdmListSetting{
    "ldm_list", "max64 | cas | sbuffer", "\"max64\"",
    "how the lists are built: 64-bit atomicMax, the paper's compare-and-swap, or count-scan-fill-sort"};
const EffectSetting kLdmBuildSetting{
    "ldm_build", "hardware | 3dr", "\"hardware\"",
    "one instanced draw over the N maps, or compute 3D rasterization per (triangle, map)"};

const EffectDef& ambientOcclusionEffect() {
  static const EffectDef def{
      .name = "ambient_occlusion",
      .summary =
          "ambient occlusion of the scene's ambient term: layered depth maps along N directions, the same "
          "directions ray traced, or a Monte Carlo reference",
      .defaultValue = false,
      .validate = validateAo,
      .needs = {FrameResource::Depth},
      .passes = {kLdmBuildPass, kAmbientOcclusionPass},
      .cannotAct = aoCannotAct,
      .needsOf = aoNeedsOf,
      .passesOf = aoPassesOf,
      .build = buildAmbientOcclusion,
      .report = reportAmbientOcclusion,
      .table = aoTableMarkdown,
      .settings =
          {
              {"method", "ldm | raytraced | reference | hbao | gtao", "\"ldm\"",
               "layered depth maps along N directions; the same N directions ray traced; cosine-weighted Monte "
               "Carlo (the converged reference); screen-space HBAO; screen-space GTAO (XeGTAO: N slices)"},
              {"directions", "1..2048", "64",
               "N: the LDM directions (each traced both ways); hbao: screen directions; gtao: slices"},
              kLdmResolutionSetting,
              {"d_max", "a number > 0, or null", "null", "obscurance: occluders farther than this (m) do not count"},
              kLdmBiasSetting,
              kLdmListSetting,
              kLdmBuildSetting,
              {"samples", "a square in 16..65536", "1024", "reference rays per pixel (side x side strata)"},
              {"steps", "1..1024", "32", "hbao: samples per screen direction; gtao: samples on each side of a slice"},
          },
  };
  return def;
}

}  // namespace hb
