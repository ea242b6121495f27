// Config files: the top-level schema (config.h), sweep expansion, the effective config, CPU lowering.
#include "config/config.h"
#include "scene/hard_cases.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "base/errors.h"
#include "base/input_file.h"
#include "base/text_format.h"
#include "config/config_reader.h"
#include "plan/effects.h"
#include "scene/ambient_json.h"
#include "scene/camera.h"
#include "scene/environment.h"

namespace hb {

using namespace config_reader;  // Json, Where and the strict readers

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Enough runs for any real sweep; a larger grid is almost surely a typo (an extra axis).
constexpr size_t kMaxRuns = 10000;
// gltf_io.cpp's floor for eq. 4.1 ranges, so that a light of intensity 0 still has a valid sphere.
constexpr float kMinEq41Range = 1e-3f;
// CPU devices (lavapipe) render about 3 orders of magnitude slower than a GPU.
constexpr uint32_t kCpuMaxWidth = 480, kCpuMaxHeight = 270, kCpuWarmup = 2, kCpuMeasured = 5;
// Ambient occlusion on a CPU device: at most 64 maps of 128² (about 10 s a frame on 2 cores), 256
// reference rays (a square) and 32 HBAO steps.
constexpr int64_t kCpuAoDirections = 64, kCpuAoResolution = 128, kCpuAoSamples = 256, kCpuAoSteps = 32;
constexpr int64_t kCpuIndirectSamples = 64, kCpuIndirectPhotons = 4;  // the gathered reference and photons a face side

const std::vector<std::string_view> kTopKeys = {"name",   "description", "scene",       "scene_params", "camera",
                                                "lights", "ambient",     "environment", "resolution",   "effects",
                                                "frames", "defaults",    "variants",    "grid",         "notes"};

// Floats print as the shortest decimal that reads back to the same float (0.1f → 0.1, not
// 0.10000000149011612), so the effective config reads like the file it came from.
double cleanFloat(float f) {
  char buffer[32];
  auto result = std::to_chars(buffer, buffer + sizeof buffer, f);
  double d = 0.0;
  std::from_chars(buffer, result.ptr, d);
  return d;
}

nlohmann::json vecJson(glm::vec3 v) { return {cleanFloat(v.x), cleanFloat(v.y), cleanFloat(v.z)}; }

glm::vec3 readVec3(const Json& v, const Where& where, const char* shape) {
  std::vector<float> n = readFloats(v, where, 3, shape);
  return glm::vec3(n[0], n[1], n[2]);
}

bool isGltfPath(const std::string& s) {
  const std::string ext = asciiLower(std::filesystem::path(s).extension().string());
  return ext == ".gltf" || ext == ".glb";
}

void parseScene(Config& c, const Json& doc, const Where& top) {
  if (doc.contains("scene")) {
    Where w = top.key("scene");
    std::string s = readString(doc["scene"], w);
    const std::vector<std::string> builtins = allSceneNames();
    if (std::find(builtins.begin(), builtins.end(), s) != builtins.end()) {
      c.scene = s;  // the atrium or a hard case (hard_cases.h)
    } else if (isGltfPath(s)) {
      std::filesystem::path p(s);
      // Absolute, so that the effective config in a results file names the same file from anywhere.
      if (p.is_relative()) p = std::filesystem::absolute(std::filesystem::path(c.sourceName).parent_path() / p);
      c.scene = p.lexically_normal().string();
    } else {
      w.fail("\"" + s + "\" is neither a built-in scene (" + unknownSceneHint(s) + ") nor a .gltf/.glb path");
    }
  }
  if (doc.contains("scene_params")) {
    Where w = top.key("scene_params");
    if (!c.sceneIsBuiltin())
      w.fail("applies only to the built-in \"atrium\" scene; remove it or set \"scene\": \"atrium\"");
    const Json& sp = doc["scene_params"];
    requireObjectWithKeys(sp, w, {"triangle_scale", "lights", "seed", "light_range"});
    if (sp.contains("triangle_scale"))
      c.sceneParams.triangleScale =
          readNumber(sp["triangle_scale"], w.key("triangle_scale"), kMinTriangleScale, kMaxTriangleScale, false);
    if (sp.contains("lights"))
      c.sceneParams.lightCount = uint32_t(readInt(sp["lights"], w.key("lights"), 0, kMaxLightCount));
    if (sp.contains("seed")) c.sceneParams.seed = uint32_t(readInt(sp["seed"], w.key("seed"), 0, UINT32_MAX));
    if (sp.contains("light_range")) {
      const std::vector<double> r = readNumbers(sp["light_range"], w.key("light_range"), 2, "[min, max] in metres");
      if (!(r[0] > 0.0 && r[0] <= r[1] && r[1] < 1e6))
        w.key("light_range")
            .fail(describe(sp["light_range"]) + " is not a range; use [min, max] with 0 < min <= max < 1e6");
      c.sceneParams.lightRangeMin = r[0];
      c.sceneParams.lightRangeMax = r[1];
    }
  }
}

void parseCamera(CameraSpec& cam, const Json& v, const Where& w) {
  if (v.is_string()) {
    if (v.get<std::string>() != "auto")
      w.fail(describe(v) +
             " is not \"auto\"; give \"auto\" (frame the scene's bounds), {\"index\": N} or "
             "{\"position\", \"target\"}");
    cam.autoFrame = true;
    return;
  }
  requireObjectWithKeys(v, w, {"index", "position", "target", "up", "yfov_deg", "znear", "zfar"});
  if (v.contains("index")) {
    if (v.size() != 1)
      w.fail(
          "give either \"index\" (a camera of the scene) or \"position\" and \"target\" (with optional "
          "\"up\", \"yfov_deg\", \"znear\", \"zfar\"), not both");
    cam.index = uint32_t(readInt(v["index"], w.key("index"), 0, UINT32_MAX));
    return;
  }
  for (const char* required : {"position", "target"})
    if (!v.contains(required))
      w.fail(std::string("missing \"") + required + "\"; give \"position\" and \"target\", or \"index\"");
  cam.explicitPose = true;
  cam.position = readVec3(v["position"], w.key("position"), "[x, y, z]");
  cam.target = readVec3(v["target"], w.key("target"), "[x, y, z]");
  if (v.contains("up")) cam.up = readVec3(v["up"], w.key("up"), "[x, y, z]");
  if (v.contains("yfov_deg")) cam.yfovDeg = float(readNumber(v["yfov_deg"], w.key("yfov_deg"), 1.0, 179.0, false));
  if (v.contains("znear")) cam.znear = readFloat(v["znear"], w.key("znear"), 0.0, kInf, true);
  if (v.contains("zfar")) cam.zfar = readFloat(v["zfar"], w.key("zfar"), 0.0, kInf, true);
  if (!(cam.zfar > cam.znear)) w.key("zfar").fail("must be greater than znear (" + std::to_string(cam.znear) + ")");
  glm::vec3 forward = cam.target - cam.position;
  if (glm::length(forward) == 0.0f) w.key("target").fail("must differ from position");
  // lookAt needs a view direction that is not parallel to up; 1e-6 of the product of lengths is
  // far below any deliberate choice and far above float round-off of a parallel pair.
  if (glm::length(glm::cross(forward, cam.up)) <= 1e-6f * glm::length(forward) * glm::length(cam.up))
    w.key("up").fail("must not be zero or parallel to target - position");
  // lookAt works in float: from about 1.8e19 (target - position, or up) its squared lengths
  // overflow and the view is NaN or collapses (position [-3e38, 0, 0] with target [3e38, 0, 0]
  // passed the checks above). A view is finite and its rotation has determinant 1.
  const glm::mat4 view = lookAt(cam.position, cam.target, cam.up);
  bool isView = std::abs(glm::determinant(glm::mat3(view)) - 1.0f) < 1e-3f;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) isView = isView && std::isfinite(view[c][r]);
  if (!isView) w.fail("position, target and up give no view in float; give them in metres below 1e19");
}

Light parseLight(const Json& v, const Where& w) {
  requireObjectWithKeys(v, w,
                        {"type", "name", "position", "direction", "color", "intensity", "range", "inner_cone_deg",
                         "outer_cone_deg", "cast_shadows"});
  if (!v.contains("type")) w.fail("missing \"type\" (\"point\", \"spot\" or \"directional\")");
  Light l;
  l.type = LightType(readChoice(v["type"], w.key("type"), {"point", "spot", "directional"}));
  const char* typeName = l.type == LightType::Point ? "point" : l.type == LightType::Spot ? "spot" : "directional";
  bool positioned = l.type != LightType::Directional, aimed = l.type != LightType::Point;
  auto notFor = [&](const char* key, bool applies) {
    if (v.contains(key) && !applies)
      w.key(key).fail(std::string("does not apply to a ") + typeName + " light; remove it");
  };
  notFor("position", positioned);
  notFor("range", positioned);
  notFor("direction", aimed);
  notFor("inner_cone_deg", l.type == LightType::Spot);
  notFor("outer_cone_deg", l.type == LightType::Spot);
  if (positioned && !v.contains("position")) w.fail(std::string("a ") + typeName + " light needs \"position\"");
  if (aimed && !v.contains("direction")) w.fail(std::string("a ") + typeName + " light needs \"direction\"");

  if (v.contains("name")) l.name = readString(v["name"], w.key("name"));
  if (positioned) l.position = readVec3(v["position"], w.key("position"), "[x, y, z]");
  if (aimed) {
    // Normalised in double: a float length overflows from components of about 1.8e19 and made
    // [0.3, -1, 2e31] the zero direction (found by fuzz_config).
    const glm::dvec3 d(readVec3(v["direction"], w.key("direction"), "[x, y, z]"));
    if (glm::length(d) == 0.0) w.key("direction").fail("must not be zero");
    l.direction = glm::vec3(d / glm::length(d));
  }
  if (v.contains("color")) {
    l.color = readVec3(v["color"], w.key("color"), "[r, g, b]");
    for (int i = 0; i < 3; ++i)
      if (l.color[i] < 0.0f) w.key("color").index(size_t(i)).fail(describe(v["color"][i]) + " is negative");
  }
  if (v.contains("intensity")) l.intensity = readFloat(v["intensity"], w.key("intensity"), 0.0, kInf, false);
  if (v.contains("range")) {
    l.range = readFloat(v["range"], w.key("range"), 0.0, kInf, true);
  } else if (positioned) {
    l.range = std::max(float(rangeFromIntensity(l.intensity)), kMinEq41Range);  // thesis eq. 4.1
    l.rangeFromEq41 = true;
  } else {
    l.range = 0.0f;  // as gltf_io: a directional light reaches everywhere
  }
  if (l.type == LightType::Spot) {
    double inner = 0.0, outer = 45.0;  // glTF defaults: 0 and pi/4
    if (v.contains("inner_cone_deg"))
      inner = readNumber(v["inner_cone_deg"], w.key("inner_cone_deg"), 0.0, 90.0, false);
    if (v.contains("outer_cone_deg")) outer = readNumber(v["outer_cone_deg"], w.key("outer_cone_deg"), 0.0, 90.0, true);
    if (!(inner < outer))
      w.key("inner_cone_deg")
          .fail(describe(Json(inner)) + " must be less than outer_cone_deg (" + describe(Json(outer)) + ")");
    l.innerConeAngle = float(glm::radians(inner));
    l.outerConeAngle = float(glm::radians(outer));
  }
  if (v.contains("cast_shadows")) l.castShadows = readBool(v["cast_shadows"], w.key("cast_shadows"));
  return l;
}

nlohmann::json lightJson(const Light& l) {
  nlohmann::json j;
  const char* types[] = {"point", "spot", "directional"};
  j["type"] = types[uint32_t(l.type)];
  if (!l.name.empty()) j["name"] = l.name;
  if (l.type != LightType::Directional) {
    j["position"] = vecJson(l.position);
    j["range"] = cleanFloat(l.range);
  }
  if (l.type != LightType::Point) j["direction"] = vecJson(l.direction);
  j["color"] = vecJson(l.color);
  j["intensity"] = cleanFloat(l.intensity);
  if (l.type == LightType::Spot) {
    // Degrees at 1e-4: the float radians hold about 7 digits, so more would print only round-off.
    auto deg = [](float r) { return std::round(glm::degrees(double(r)) * 1e4) / 1e4; };
    j["inner_cone_deg"] = deg(l.innerConeAngle);
    j["outer_cone_deg"] = deg(l.outerConeAngle);
  }
  j["cast_shadows"] = l.castShadows;
  return j;
}

// Every run's name and where it came from, in expansion order (used for expansion and for the
// duplicate-name check, which must agree).
struct PlannedRun {
  std::string name;
  VariantParams params;
  std::string origin;  // "variants[1]" or "grid"
};

// Fits a resolution inside cap by an integer divisor (exact aspect when it divides both sides).
std::array<uint32_t, 2> capResolution(std::array<uint32_t, 2> r, std::array<uint32_t, 2> cap) {
  if (cap[0] == 0) return r;
  uint32_t k = std::max({1u, (r[0] + cap[0] - 1) / cap[0], (r[1] + cap[1] - 1) / cap[1]});
  return {std::max(1u, r[0] / k), std::max(1u, r[1] / k)};
}

std::vector<PlannedRun> planRuns(const Config& c) {
  std::vector<PlannedRun> runs;
  for (size_t i = 0; i < c.variants.size(); ++i)
    runs.push_back({c.variants[i].name, c.variants[i].params, "variants[" + std::to_string(i) + "]"});
  if (!c.grid.empty()) {
    // An odometer over the axes; the last axis turns fastest, so the first varies slowest.
    std::vector<size_t> digit(c.grid.size(), 0);
    Where scratch{c.sourceName, "grid"};
    while (true) {
      PlannedRun run{"", c.defaults, "grid"};
      for (size_t a = 0; a < c.grid.size(); ++a) {
        const GridAxis& axis = c.grid[a];
        const Json value = Json(axis.values[digit[a]]);
        applyParam(run.params, axis.key, value, scratch.key(axis.key), scratch);
        run.name += (a ? ", " : "") + axis.key + "=" + valueLabel(value);
      }
      runs.push_back(std::move(run));
      size_t a = c.grid.size();
      while (a > 0 && ++digit[a - 1] == c.grid[a - 1].values.size()) digit[--a] = 0;
      if (a == 0) break;
    }
  }
  if (runs.empty()) runs.push_back({"default", c.defaults, "defaults"});
  return runs;
}

void parseGrid(Config& c, const Json& g, const Where& w) {
  if (!g.is_object()) w.fail("expected an object of parameter: [values], got " + describe(g));
  if (g.empty()) w.fail("is empty; remove it or give at least one parameter with a list of values");
  size_t runs = 1;
  for (const auto& item : g.items()) {
    const std::vector<std::string_view>& keys = paramKeys();
    if (std::find(keys.begin(), keys.end(), item.key()) == keys.end()) failUnknownKey(item.key(), w, keys);
    Where axisWhere = w.key(item.key());
    if (!item.value().is_array() || item.value().empty())
      axisWhere.fail("expected a non-empty list of values, got " + describe(item.value()));
    GridAxis axis{item.key(), {}};
    for (size_t i = 0; i < item.value().size(); ++i) {
      const Json& value = item.value()[i];
      VariantParams probe = c.defaults;
      applyParam(probe, item.key(), value, axisWhere.index(i), w);
      checkParamsFitScene(c, probe, axisWhere.index(i).prefix());
      for (size_t k = 0; k < i; ++k)
        if (item.value()[k] == value)
          axisWhere.index(i).fail(describe(value) + " is already in the list at [" + std::to_string(k) + "]");
      axis.values.push_back(nlohmann::json(value));
    }
    runs *= axis.values.size();
    if (runs > kMaxRuns)
      w.fail("expands to more than " + std::to_string(kMaxRuns) + " runs; split the sweep or drop an axis");
    c.grid.push_back(std::move(axis));
  }
}

Config parseDocument(const Json& doc, const std::string& sourceName) {
  Config c;
  c.sourceName = sourceName;
  Where top{sourceName, ""};
  if (!doc.is_object()) top.fail("expected a JSON object at the top level, got " + describe(doc));
  requireObjectWithKeys(doc, top, kTopKeys);

  if (!doc.contains("name")) top.fail("missing \"name\"; every config needs one, e.g. \"name\": \"my-sweep\"");
  c.name = readString(doc["name"], top.key("name"));
  bool nameOk = !c.name.empty() && std::all_of(c.name.begin(), c.name.end(), [](unsigned char ch) {
    return std::isalnum(ch) || ch == '.' || ch == '_' || ch == '-';
  });
  if (!nameOk)
    top.key("name").fail(describe(doc["name"]) +
                         " may use only letters, digits, '.', '_' and '-' (it names output files)");
  if (doc.contains("description")) c.description = readString(doc["description"], top.key("description"));

  parseScene(c, doc, top);
  if (doc.contains("camera")) parseCamera(c.camera, doc["camera"], top.key("camera"));
  if (doc.contains("lights")) {
    const Json& l = doc["lights"];
    Where w = top.key("lights");
    if (l.is_string()) {
      if (l.get<std::string>() != "scene")
        w.fail(describe(l) + " is not \"scene\"; give \"scene\" or a list of lights");
    } else if (l.is_array()) {
      c.lights.emplace();
      for (size_t i = 0; i < l.size(); ++i) c.lights->push_back(parseLight(l[i], w.index(i)));
    } else {
      w.fail("expected \"scene\" or a list of lights, got " + describe(l));
    }
    if (c.lights && doc.contains("scene_params") && doc["scene_params"].contains("lights"))
      top.key("scene_params").key("lights").fail("cannot be combined with an explicit \"lights\" list; remove one");
  }
  if (doc.contains("ambient")) c.ambient = readAmbient(doc["ambient"], top.key("ambient"));
  if (doc.contains("environment"))
    c.environment =
        readEnvironment(doc["environment"], top.key("environment"), std::filesystem::path(c.sourceName).parent_path());
  if (doc.contains("effects")) {
    validateEffects(doc["effects"], top.key("effects"));  // the schema of plan/effects.h
    c.effects = nlohmann::json(doc["effects"]);
  }
  if (doc.contains("frames")) {
    Where w = top.key("frames");
    requireObjectWithKeys(doc["frames"], w, {"warmup", "measured"});
    const Json& f = doc["frames"];
    if (f.contains("warmup")) c.warmupFrames = uint32_t(readInt(f["warmup"], w.key("warmup"), 0, 100000));
    if (f.contains("measured")) c.measuredFrames = uint32_t(readInt(f["measured"], w.key("measured"), 1, 1000000));
  }

  // Defaults: built-in, then the top-level resolution, then the atrium's scene_params, then "defaults".
  if (doc.contains("resolution")) {
    if (doc.contains("defaults") && doc["defaults"].is_object() && doc["defaults"].contains("resolution"))
      top.key("defaults").key("resolution").fail("is also given at the top level as \"resolution\"; keep one");
    applyParam(c.defaults, "resolution", doc["resolution"], top.key("resolution"), top);
  }
  if (c.sceneIsBuiltin()) {
    c.defaults.triangleScale = c.sceneParams.triangleScale;
    if (!c.lights) c.defaults.lightCount = c.sceneParams.lightCount;
  }
  if (doc.contains("defaults")) {
    applyParams(c.defaults, doc["defaults"], top.key("defaults"));
    checkParamsFitScene(c, c.defaults, top.key("defaults").prefix());
  }

  if (doc.contains("variants")) {
    Where w = top.key("variants");
    const Json& vs = doc["variants"];
    if (!vs.is_array()) w.fail("expected a list of {\"name\": ..., \"params\": {...}}, got " + describe(vs));
    for (size_t i = 0; i < vs.size(); ++i) {
      Where vw = w.index(i);
      requireObjectWithKeys(vs[i], vw, {"name", "params"});
      if (!vs[i].contains("name")) vw.fail("missing \"name\"; every variant needs one");
      Variant v{readString(vs[i]["name"], vw.key("name")), c.defaults};
      if (v.name.empty()) vw.key("name").fail("is empty; give the variant a name");
      if (vs[i].contains("params")) {
        applyParams(v.params, vs[i]["params"], vw.key("params"));
        checkParamsFitScene(c, v.params, vw.key("params").prefix());
      }
      c.variants.push_back(std::move(v));
    }
  }
  if (doc.contains("grid")) parseGrid(c, doc["grid"], top.key("grid"));
  if (doc.contains("notes")) {
    Where w = top.key("notes");
    if (!doc["notes"].is_array()) w.fail("expected a list of strings, got " + describe(doc["notes"]));
    for (size_t i = 0; i < doc["notes"].size(); ++i) c.notes.push_back(readString(doc["notes"][i], w.index(i)));
  }

  std::map<std::string, std::string> seen;  // name → origin
  for (const PlannedRun& run : planRuns(c)) {
    auto [it, fresh] = seen.emplace(run.name, run.origin);
    if (fresh) continue;
    Where at = run.origin == "grid" ? top.key("grid") : top.key(run.origin).key("name");
    at.fail("the name \"" + run.name + "\" is used twice (also by " + it->second + "); names must be unique");
  }
  return c;
}

}  // namespace

bool Config::sceneIsHardCase() const {
  const std::vector<std::string> builtins = allSceneNames();
  return !sceneIsBuiltin() && std::find(builtins.begin(), builtins.end(), scene) != builtins.end();
}

void checkParamsFitScene(const Config& c, const VariantParams& p, const std::string& where) {
  // light_count works on any scene: the atrium draws its own lights, any other scene gets that
  // many automatic ones (app/auto_scene.h).
  if (!c.sceneIsBuiltin() && p.triangleScale)
    throw InputError(where + ": triangle_scale applies only to the built-in \"atrium\" scene (this config renders " +
                     c.scene + "); remove it");
  if (c.lights && p.lightCount) {
    throw InputError(where + ": light_count cannot be combined with the config's explicit \"lights\" list; remove one");
  }
}

Config parseConfig(const nlohmann::ordered_json& doc, const std::string& sourceName) {
  return parseDocument(doc, sourceName);
}

Config parseConfig(const nlohmann::json& doc, const std::string& sourceName) {
  return parseDocument(nlohmann::ordered_json(doc), sourceName);
}

Config loadConfig(const std::string& path) {
  const std::string text = readInputText(path, "give the path of a config JSON file (e.g. configs/thesis.json)");
  return parseDocument(parseText(text, path), path);
}

std::vector<Variant> expandVariants(const Config& c) {
  std::vector<Variant> out;
  for (PlannedRun& run : planRuns(c)) {
    run.params.resolution = capResolution(run.params.resolution, c.resolutionCap);
    out.push_back({std::move(run.name), run.params});
  }
  return out;
}

nlohmann::json toJson(const Config& c) {
  nlohmann::json j;
  j["name"] = c.name;
  j["description"] = c.description;
  j["scene"] = c.scene;
  if (c.sceneIsBuiltin()) {
    j["scene_params"] = {{"triangle_scale", c.sceneParams.triangleScale}, {"seed", c.sceneParams.seed}};
    if (!c.lights) j["scene_params"]["lights"] = c.sceneParams.lightCount;
    if (c.sceneParams.lightRangeMax > 0.0)
      j["scene_params"]["light_range"] = {c.sceneParams.lightRangeMin, c.sceneParams.lightRangeMax};
  }
  if (c.camera.autoFrame)
    j["camera"] = "auto";
  else if (c.camera.explicitPose)
    j["camera"] = {{"position", vecJson(c.camera.position)},
                   {"target", vecJson(c.camera.target)},
                   {"up", vecJson(c.camera.up)},
                   {"yfov_deg", cleanFloat(c.camera.yfovDeg)},
                   {"znear", cleanFloat(c.camera.znear)},
                   {"zfar", cleanFloat(c.camera.zfar)}};
  else
    j["camera"] = {{"index", c.camera.index}};
  if (c.lights) {
    j["lights"] = nlohmann::json::array();
    for (const Light& l : *c.lights) j["lights"].push_back(lightJson(l));
  } else {
    j["lights"] = "scene";
  }
  if (c.ambient) j["ambient"] = toJson(*c.ambient);
  if (c.environment) j["environment"] = toJson(*c.environment);
  j["effects"] = c.effects;  // as the file says: what it leaves out stays the scene's (or the default)
  j["frames"] = {{"warmup", c.warmupFrames}, {"measured", c.measuredFrames}};
  j["defaults"] = toJson(c.defaults);
  j["variants"] = nlohmann::json::array();
  for (const Variant& v : expandVariants(c)) j["variants"].push_back({{"name", v.name}, {"params", toJson(v.params)}});
  j["notes"] = c.notes;
  return j;
}

Config embeddedDefaultConfig() {
  std::string_view text = embeddedDefaultConfigText();
  const std::string source = "thesis.json (embedded)";
  return parseDocument(parseText(std::string(text), source), source);
}

Config lowerForCpuDevice(Config c, const CpuFrameOverrides& given) {
  std::vector<Variant> before = expandVariants(c);
  uint32_t warmup = c.warmupFrames, measured = c.measuredFrames;
  c.resolutionCap = {kCpuMaxWidth, kCpuMaxHeight};
  c.warmupFrames = given.warmup ? *given.warmup : std::min(c.warmupFrames, kCpuWarmup);
  c.measuredFrames = given.measured ? *given.measured : std::min(c.measuredFrames, kCpuMeasured);
  c.defaults.resolution = capResolution(c.defaults.resolution, c.resolutionCap);
  std::vector<Variant> after = expandVariants(c);

  auto label = [](std::array<uint32_t, 2> r) { return std::to_string(r[0]) + "x" + std::to_string(r[1]); };
  std::vector<std::string> changes;
  std::set<std::string> resolutions;  // "1920x1080 -> 480x270", each once, in a stable order
  for (size_t i = 0; i < before.size(); ++i)
    if (before[i].params.resolution != after[i].params.resolution)
      resolutions.insert("resolution " + label(before[i].params.resolution) + " -> " +
                         label(after[i].params.resolution));
  changes.assign(resolutions.begin(), resolutions.end());
  if (given.warmup)
    changes.push_back("warmup " + std::to_string(c.warmupFrames) + " (--warmup)");
  else if (warmup != c.warmupFrames)
    changes.push_back("warmup " + std::to_string(warmup) + " -> " + std::to_string(c.warmupFrames));
  if (given.measured)
    changes.push_back("measured frames " + std::to_string(c.measuredFrames) + " (--frames)");
  else if (measured != c.measuredFrames)
    changes.push_back("measured frames " + std::to_string(measured) + " -> " + std::to_string(c.measuredFrames));

  // Ambient occlusion's and the indirect light's sizes scale a CPU device's work as much as the
  // resolution does (512 maps of 256² take minutes a frame on lavapipe): they are capped too,
  // wherever an effects object sets them.
  std::set<std::string> aoChanges;
  auto capEffect = [&](nlohmann::json& effects, const char* effect,
                       const std::vector<std::pair<std::string, int64_t>>& caps) {
    if (!effects.is_object() || !effects.contains(effect) || !effects[effect].is_object()) return;
    nlohmann::json& e = effects[effect];
    for (const auto& [key, cap] : caps)
      if (e.contains(key) && e[key].is_number_integer() && e[key].get<int64_t>() > cap) {
        aoChanges.insert(std::string(effect) + " " + key + " " + std::to_string(e[key].get<int64_t>()) + " -> " +
                         std::to_string(cap));
        e[key] = cap;
      }
  };
  auto capAo = [&](nlohmann::json& effects) {
    capEffect(effects, "ambient_occlusion",
              {{"directions", kCpuAoDirections},
               {"ldm_resolution", kCpuAoResolution},
               {"samples", kCpuAoSamples},
               {"steps", kCpuAoSteps}});
    capEffect(effects, "indirect",
              {{"directions", kCpuAoDirections},
               {"ldm_resolution", kCpuAoResolution},
               {"samples", kCpuIndirectSamples},
               {"photons", kCpuIndirectPhotons}});
    capEffect(effects, "environment_light",
              {{"directions", kCpuAoDirections}, {"ldm_resolution", kCpuAoResolution}, {"samples", kCpuAoSamples}});
  };
  capAo(c.effects);
  capAo(c.defaults.effects);
  for (Variant& v : c.variants) capAo(v.params.effects);
  changes.insert(changes.end(), aoChanges.begin(), aoChanges.end());

  std::string note;
  for (const std::string& change : changes) note += (note.empty() ? "" : ", ") + change;
  if (note.empty())
    note = "CPU device: the config already fits its limits (" + label(c.resolutionCap) + ", " +
           std::to_string(kCpuWarmup) + " warm-up and " + std::to_string(kCpuMeasured) + " measured frames)";
  else
    note = "lowered for a CPU device (" + note + "); variant names keep the full-size values";
  c.notes.push_back(note + "; times are not comparable with GPU runs");
  return c;
}

Camera cameraFromSpec(const CameraSpec& spec) {
  HB_ASSERT(spec.explicitPose);
  Camera cam;
  cam.name = "config";
  cam.view = lookAt(spec.position, spec.target, spec.up);
  cam.yfov = glm::radians(spec.yfovDeg);
  cam.znear = spec.znear;
  cam.zfar = spec.zfar;
  return cam;
}

}  // namespace hb
