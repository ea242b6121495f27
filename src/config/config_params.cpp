// VariantParams: reading one parameter strictly, writing them back, and --set key=value.
#include <charconv>

#include "config/config.h"
#include "config/config_reader.h"
#include "base/errors.h"
#include "effects/effects.h"

namespace hb {

using config_reader::Json;
using config_reader::Where;

const char* toString(NormalCulling v) {
  switch (v) {
    case NormalCulling::Off: return "off";
    case NormalCulling::Naive: return "naive";
    case NormalCulling::Improved: return "improved";
    case NormalCulling::Geometric: return "geometric";
  }
  return "?";
}

const char* toString(RtBackend v) {
  switch (v) {
    case RtBackend::Auto: return "auto";
    case RtBackend::RayQuery: return "rayquery";
    case RtBackend::Pipeline: return "pipeline";
  }
  return "?";
}

const char* toString(WorldPosMethod v) {
  switch (v) {
    case WorldPosMethod::Alg41: return "alg41";
    case WorldPosMethod::Matrix: return "matrix";
    case WorldPosMethod::Hit: return "hit";
  }
  return "?";
}

const char* toString(ShadingMethod v) { return v == ShadingMethod::Forward ? "forward" : "visbuffer"; }

const char* toString(LightLists v) {
  switch (v) {
    case LightLists::Tile: return "tile";
    case LightLists::Bitmask: return "bitmask";
    case LightLists::Zbin: return "zbin";
  }
  return "?";
}

const char* toString(PrimaryMethod v) {
  switch (v) {
    case PrimaryMethod::Hardware: return "hardware";
    case PrimaryMethod::Raster3d: return "3dr";
    case PrimaryMethod::Raster3dBinned: return "3dr-binned";
    case PrimaryMethod::Raster2d: return "2dr";
    case PrimaryMethod::RayCast: return "raycast";
  }
  return "?";
}

const char* toString(ShadowTMin v) {
  switch (v) {
    case ShadowTMin::Constant: return "constant";
    case ShadowTMin::Scaled: return "scaled";
  }
  return "?";
}

namespace config_reader {

const std::vector<std::string_view>& paramKeys() {
  static const std::vector<std::string_view> keys = {
      "tile_size", "light_culling", "aabb",         "normal_culling",      "backend",     "resolution",
      "world_pos", "range_test",    "depth_slices", "t_min",  "primary", "projection", "r3d_thread_box", "shading", "max_lights_per_tile", "light_lists", "light_count", "triangle_scale", "effects"};
  return keys;
}

void applyParam(VariantParams& p, std::string_view key, const Json& v, const Where& where,
                const Where& container) {
  if (key == "tile_size") {
    p.tileSize = uint32_t(readIntChoice(v, where, {8, 16, 32}));
  } else if (key == "light_culling") {
    p.lightCulling = readBool(v, where);
  } else if (key == "aabb") {
    p.aabb = readBool(v, where);
  } else if (key == "normal_culling") {
    static constexpr NormalCulling kNormals[] = {NormalCulling::Off, NormalCulling::Naive, NormalCulling::Improved,
                                                 NormalCulling::Geometric};
    p.normalCulling = kNormals[readChoice(v, where, {"off", "naive", "improved", "geometric"})];
  } else if (key == "backend") {
    p.backend = RtBackend(readChoice(v, where, {"auto", "rayquery", "pipeline"}));
  } else if (key == "resolution") {
    if (!v.is_array() || v.size() != 2) where.fail("expected [width, height], got " + describe(v));
    p.resolution = {uint32_t(readInt(v[0], where.index(0), 1, kMaxResolution)),
                    uint32_t(readInt(v[1], where.index(1), 1, kMaxResolution))};
  } else if (key == "world_pos") {
    static constexpr WorldPosMethod kWorldPos[] = {WorldPosMethod::Alg41, WorldPosMethod::Matrix, WorldPosMethod::Hit};
    p.worldPos = kWorldPos[readChoice(v, where, {"alg41", "matrix", "hit"})];
  } else if (key == "range_test") {
    p.rangeTest = readBool(v, where);
  } else if (key == "depth_slices") {
    int64_t n = readInt(v, where, 0, 32);
    if (n == 1) where.fail("1 is not allowed: use 0 (off) or 2..32 slices");
    p.depthSlices = uint32_t(n);
  } else if (key == "t_min") {
    p.tMin = ShadowTMin(readChoice(v, where, {"constant", "scaled"}));
  } else if (key == "primary") {
    p.primary = PrimaryMethod(readChoice(v, where, {"hardware", "3dr", "3dr-binned", "2dr", "raycast"}));
  } else if (key == "projection") {
    p.projection = CameraProjection(readChoice(v, where, {"perspective", "orthographic", "paraboloid", "latlong"}));
  } else if (key == "shading") {
    p.shading = ShadingMethod(readChoice(v, where, {"forward", "visbuffer"}));
  } else if (key == "r3d_thread_box") {
    p.r3dThreadBox = uint32_t(readInt(v, where, 1, 65536));
  } else if (key == "max_lights_per_tile") {
    int64_t n = readInt(v, where, 32, 1024);
    // The visibility bitmask holds one 32-bit word per 32 lights of a tile.
    if (n % 32 != 0) where.fail(std::to_string(n) + " is not a multiple of 32");
    p.maxLightsPerTile = uint32_t(n);
  } else if (key == "light_lists") {
    static constexpr LightLists kLists[] = {LightLists::Tile, LightLists::Bitmask, LightLists::Zbin};
    p.lightLists = kLists[readChoice(v, where, {"tile", "bitmask", "zbin"})];
  } else if (key == "light_count") {
    p.lightCount = uint32_t(readInt(v, where, 0, kMaxLightCount));
  } else if (key == "triangle_scale") {
    p.triangleScale = readNumber(v, where, kMinTriangleScale, kMaxTriangleScale, /*loExclusive=*/false);
  } else if (key == "effects") {
    validateEffects(v, where);  // the schema of effects/effects.h
    p.effects = nlohmann::json(v);
  } else {
    failUnknownKey(key, container, paramKeys());
  }
}

void applyParams(VariantParams& p, const Json& object, const Where& where) {
  requireObjectWithKeys(object, where, paramKeys());
  for (const auto& item : object.items())
    applyParam(p, item.key(), item.value(), where.key(item.key()), where);
}

std::string valueLabel(const Json& value) {
  if (value.is_string()) return value.get<std::string>();
  if (value.is_array() && value.size() == 2)  // a resolution
    return valueLabel(value[0]) + "x" + valueLabel(value[1]);
  return value.dump();
}

}  // namespace config_reader

nlohmann::json toJson(const VariantParams& p) {
  nlohmann::json j;
  j["tile_size"] = p.tileSize;
  j["light_culling"] = p.lightCulling;
  j["aabb"] = p.aabb;
  j["normal_culling"] = toString(p.normalCulling);
  j["backend"] = toString(p.backend);
  j["resolution"] = {p.resolution[0], p.resolution[1]};
  j["world_pos"] = toString(p.worldPos);
  j["range_test"] = p.rangeTest;
  j["depth_slices"] = p.depthSlices;
  j["t_min"] = toString(p.tMin);
  j["primary"] = toString(p.primary);
  j["r3d_thread_box"] = p.r3dThreadBox;
  if (p.projection) j["projection"] = toString(*p.projection);
  j["shading"] = toString(p.shading);
  j["max_lights_per_tile"] = p.maxLightsPerTile;
  j["light_lists"] = toString(p.lightLists);
  if (p.lightCount) j["light_count"] = *p.lightCount;
  if (p.triangleScale) j["triangle_scale"] = *p.triangleScale;
  if (!p.effects.is_null()) j["effects"] = p.effects;
  return j;
}

void applySetOverride(VariantParams& params, const std::string& keyEqualsValue) {
  Where where{"--set " + keyEqualsValue, ""};
  size_t eq = keyEqualsValue.find('=');
  if (eq == std::string::npos || eq == 0)
    where.fail(
        "expected key=value, e.g. --set tile_size=16 (keys: tile_size, light_culling, aabb, "
        "normal_culling, backend, resolution, world_pos, range_test, depth_slices, t_min, primary, projection, "
        "r3d_thread_box, shading, max_lights_per_tile, light_lists, light_count, triangle_scale, effects)");
  std::string key = keyEqualsValue.substr(0, eq);
  std::string text = keyEqualsValue.substr(eq + 1);

  // A value is JSON when it parses as JSON (16, true, [640,360]); otherwise a bare word (improved).
  Json value = Json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (value.is_discarded()) value = text;
  if (key == "resolution" && value.is_string()) {  // 1920x1080
    const std::string& s = value.get_ref<const std::string&>();
    size_t x = s.find('x');
    uint64_t w = 0, h = 0;
    bool ok = x != std::string::npos && std::from_chars(s.data(), s.data() + x, w).ptr == s.data() + x &&
              x > 0 && std::from_chars(s.data() + x + 1, s.data() + s.size(), h).ptr == s.data() + s.size() &&
              x + 1 < s.size();
    if (!ok) where.key(key).fail("expected WIDTHxHEIGHT (e.g. 1920x1080) or [w, h], got \"" + s + "\"");
    value = Json::array({w, h});
  }
  config_reader::applyParam(params, key, value, where.key(key), where);
}

}  // namespace hb
