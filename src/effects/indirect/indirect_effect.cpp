#include "effects/indirect/indirect_effect.h"

#include <algorithm>

#include "base/errors.h"

#include "effects/ambient_occlusion/ao_effect.h"
#include "effects/indirect/indirect_part.h"
#include "effects/indirect/indirect_table.h"
#include "shared/gpu_types.h"

namespace hb {

const char* toString(IndirectMethod m) {
  switch (m) {
    case IndirectMethod::Ldm: return "ldm";
    case IndirectMethod::RayTraced: return "raytraced";
    case IndirectMethod::Reference: return "reference";
  }
  return "?";
}

const char* toString(IndirectSplat s) { return s == IndirectSplat::Raster ? "raster" : "compute"; }

namespace {

IndirectSettings readIndirect(const nlohmann::ordered_json& value, const json_reader::Where& where) {
  using namespace json_reader;
  IndirectSettings s;
  if (!validateEffectValue(indirectEffect(), value, where)) return s;  // true, false or an object of its settings
  if (value.contains("method"))
    s.method = IndirectMethod(readChoice(value["method"], where.key("method"), {"ldm", "raytraced", "reference"}));
  readLdmSettings(value, where, s);
  if (value.contains("photons")) s.photons = uint32_t(readInt(value["photons"], where.key("photons"), 1, 1024));
  if (value.contains("splat"))
    s.splat = IndirectSplat(readChoice(value["splat"], where.key("splat"), {"compute", "raster"}));
  if (value.contains("max_anisotropy")) {
    const json_reader::Where w = where.key("max_anisotropy");
    s.maxAnisotropy = readNumber(value["max_anisotropy"], w, 0.0, 1e6, false);
    if (s.maxAnisotropy > 0.0 && s.maxAnisotropy < 1.0)
      w.fail("must be 0 (off) or at least 1 (a footprint's longest axis over its shortest)");
  }
  if (value.contains("splat_bin"))
    s.splatBin = uint32_t(readIntChoice(value["splat_bin"], where.key("splat_bin"), {32, 64, 128, 256}));
  if (value.contains("footprint"))
    s.cellFootprint = readChoice(value["footprint"], where.key("footprint"), {"rotated", "cell"}) == 1;
  if (value.contains("bounces")) s.bounces = uint32_t(readInt(value["bounces"], where.key("bounces"), 1, 4));
  if (value.contains("bounce_directions"))
    s.bounceDirections = uint32_t(readInt(value["bounce_directions"], where.key("bounce_directions"), 1, 2048));
  if (value.contains("later_bounce_stride")) {
    const json_reader::Where w = where.key("later_bounce_stride");
    s.laterBounceStride = uint32_t(readIntChoice(value["later_bounce_stride"], w, {1, 2, 4, 8}));
    if (s.laterBounceStride > 1 && s.splat != IndirectSplat::Compute)
      w.fail(
          "needs splat \"compute\" (the raster splat draws every photon at every pixel); set \"splat\": "
          "\"compute\" or later_bounce_stride 1");
    // A gather tile's receivers span 16·f pixels, which must lie in one bin.
    if (s.laterBounceStride * gpu::kSplatTile > s.splatBin)
      w.fail("a stride of " + std::to_string(s.laterBounceStride) +
             " needs splat_bin >= " + std::to_string(s.laterBounceStride * gpu::kSplatTile) +
             " (its 16x16 receivers span " + std::to_string(s.laterBounceStride * gpu::kSplatTile) +
             " pixels a side); raise splat_bin or lower the "
             "stride");
  }
  readSquareSamples(value, where, s.samples);
  return s;
}

void validateIndirect(const nlohmann::ordered_json& value, const json_reader::Where& where) {
  readIndirect(value, where);
}

// Every method meets the primary photons' (or the gathered rays') surfaces through the ray tracer.
std::vector<FrameResource> indirectNeedsOf(const nlohmann::json& value) {
  if (indirectSettingsOf(value).method == IndirectMethod::Ldm)
    return {FrameResource::Depth, FrameResource::AccelerationStructures, FrameResource::LayeredDepthMaps};
  return {FrameResource::Depth, FrameResource::AccelerationStructures};
}

std::vector<const char*> indirectPassesOf(const nlohmann::json& value) {
  switch (indirectSettingsOf(value).method) {
    case IndirectMethod::Ldm: return {kIndirectLdmBuildPass, kPhotonTracePass, kPhotonSplatPass};
    case IndirectMethod::RayTraced: return {kPhotonTracePass, kPhotonSplatPass};
    case IndirectMethod::Reference: return {kIndirectGatherPass};
  }
  return {};
}

// Beyond the first bounce a photon needs the surface it landed on (its normal and albedo): the ray
// tracer returns it, and of the LDM lists only sbuffer's hold triangle ids. Where no layer chose a
// list, sbuffer is the one that works; a list the user chose is refused here, before any GPU work.
nlohmann::json completeIndirect(const nlohmann::json& value, const std::function<std::string(const char*)>& given,
                                std::vector<std::string>& notes) {
  const IndirectSettings s = indirectSettingsOf(value);
  if (s.bounces <= 1 || s.method != IndirectMethod::Ldm || s.ldmList == LdmList::Sbuffer) return value;
  const std::string why = std::to_string(s.bounces) +
                          " bounces with method ldm need ldm_list \"sbuffer\" (its lists hold the triangle ids a "
                          "photon bounces off)";
  const std::string listFrom = given("ldm_list");
  if (!listFrom.empty())
    throw InputError("effects.indirect.bounces: " + why + ", but ldm_list is " + value["ldm_list"].dump() + " (" +
                     listFrom + "); set \"ldm_list\": \"sbuffer\", or \"bounces\": 1");
  nlohmann::json completed = value;
  completed["ldm_list"] = "sbuffer";
  notes.push_back("effects.indirect.ldm_list: \"sbuffer\", chosen by the tool: " + why +
                  "; no layer chose a list (set ldm_list to choose one)");
  return completed;
}

std::string indirectCannotAct(const Scene& scene, const nlohmann::json& /*value*/) {
  const bool emits = std::any_of(scene.lights.begin(), scene.lights.end(),
                                 [](const Light& l) { return l.type != LightType::Directional && l.intensity > 0.0f; });
  if (!emits)
    return scene.lights.empty()
               ? "the scene has no lights"
               : "no point or spot light with a positive intensity (directional lights emit no photons)";
  return "";
}

}  // namespace

IndirectSettings indirectSettingsOf(const nlohmann::json& value) {
  return readIndirect(nlohmann::ordered_json(value), json_reader::Where{"effects", "indirect"});
}

nlohmann::json IndirectSettings::toJson() const {
  nlohmann::json j = {{"method", hb::toString(method)}, {"bounces", bounces}};
  if (method == IndirectMethod::Reference) {
    j["samples"] = samples;
    return j;
  }
  if (bounces > 1) {
    j["bounce_directions"] = bounceDirections;
    j["directions_per_bounce"] = nlohmann::json::array();
    for (uint32_t b = 1; b <= bounces; ++b) j["directions_per_bounce"].push_back(directionsAtBounce(b));
  }
  j["directions"] = directions;
  j["photons"] = photons;
  j["splat"] = hb::toString(splat);
  j["max_anisotropy"] = maxAnisotropy;
  j["footprint"] = cellFootprint ? "cell" : "rotated";
  if (splat == IndirectSplat::Compute) j["splat_bin"] = splatBin;
  if (splat == IndirectSplat::Compute && bounces > 1) j["later_bounce_stride"] = laterBounceStride;
  if (method == IndirectMethod::Ldm) {
    j["ldm_resolution"] = ldmResolution;
    j["bias"] = bias;
    j["ldm_list"] = hb::toString(ldmList);
    j["ldm_build"] = hb::toString(ldmBuild);
  }
  return j;
}

const EffectDef& indirectEffect() {
  static const EffectDef def{
      .name = "indirect",
      .summary =
          "single-bounce indirect light from point and spot lights: photons split into N directions, traced "
          "through layered depth maps or the ray tracer and splatted with their differentials, or a gathered "
          "reference",
      .defaultValue = false,
      .validate = validateIndirect,
      .needs = {FrameResource::Depth, FrameResource::AccelerationStructures},
      .passes = {kIndirectLdmBuildPass, kPhotonTracePass, kPhotonSplatPass, kIndirectGatherPass},
      .cannotAct = indirectCannotAct,
      .needsOf = indirectNeedsOf,
      .passesOf = indirectPassesOf,
      .complete = completeIndirect,
      .build = buildIndirect,
      .report = reportIndirect,
      .table = indirectTableMarkdown,
      .settings =
          {
              {"method", "ldm | raytraced | reference", "\"ldm\"",
               "split photons traced through layered depth maps; the same photons ray traced; the gathered single "
               "bounce (the reference)"},
              {"directions", "1..2048", "64", "N, the split directions"},
              {"ldm_resolution", "8..4096", "128", "R of each map"},
              {"photons", "1..1024", "16", "primary photons per face side (a point light emits 6 x photons^2)"},
              {"bias", "a number > 0", "1", "scale of the derived LDM bias"},
              {"splat", "compute | raster", "\"compute\"",
               "the photons binned into 16x16 tiles and gathered in slot order by compute, or drawn as quads "
               "with additive blending (the paper's); both sum the same terms in the same order"},
              {"max_anisotropy", "0, or a number >= 1", "0",
               "a stored photon's footprint at most this many times as long as it is wide: its short axis widened, "
               "its long axis and its flux kept (0: off, the paper's footprints)"},
              {"splat_bin", "32 | 64 | 128 | 256", "128",
               "splat=compute: the side in pixels of the coarse bins that list the photons for the 16x16 tiles"},
              kLdmListSetting,
              kLdmBuildSetting,
              {"samples", "a square in 16..65536", "256", "reference rays per pixel"},
              {"footprint", "rotated | cell", "\"rotated\"",
               "a split photon's directional differentials: the incoming ones rotated onto its direction (the "
               "paper's), or spanning its direction's share of the sphere"},
              {"bounces", "1..4", "1",
               "K, the diffuse bounces: each landing photon splits again (reference: paths of K bounces); with "
               "method ldm, K > 1 needs ldm_list sbuffer, which the tool takes (and says so) when no layer sets "
               "ldm_list"},
              {"bounce_directions", "1..2048", "8",
               "M: the directions a photon splits into at its second bounce, halving at each further one"},
              {"later_bounce_stride", "1 | 2 | 4 | 8", "1",
               "splat=compute with bounces > 1: bounces 2..K splatted at one receiver pixel in f x f and "
               "interpolated from the receivers on each pixel's own surface (1: every pixel, the exact splat); "
               "f x 16 <= splat_bin"},
          },
  };
  return def;
}

}  // namespace hb
