#include "config/config.h"

#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include <unistd.h>

#include <gtest/gtest.h>

#include "base/errors.h"
#include "base/input_error_of.h"
#include "config/config_overrides.h"
#include "scene/atrium.h"

namespace hb {
namespace {

const std::string kSourceDir = HYBRIDBENCH_SOURCE_DIR;
const std::string kConfigDir = kSourceDir + "/configs";

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Parses a config given as JSON text (keys kept in file order, as loadConfig does).
Config parseText(const std::string& text) { return parseConfig(nlohmann::ordered_json::parse(text), "x.json"); }

std::string errorOfText(const std::string& text) {
  return inputErrorOf([&] { parseText(text); });
}

std::vector<std::string> namesOf(const std::vector<Variant>& variants) {
  std::vector<std::string> names;
  for (const Variant& v : variants) names.push_back(v.name);
  return names;
}

const std::vector<std::string> kTable51Names = {"no optimisations",
                                                "light culling",
                                                "light culling + AABB",
                                                "light culling + AABB + shadow ray culling",
                                                "light culling + AABB + improved shadow ray culling",
                                                "improved shadow ray culling"};
const std::vector<std::string> kTable52Names = {"8x8", "16x16", "32x32"};

TEST(ShippedConfigs, EveryConfigInTheConfigsFolderParsesAndExpands) {
  size_t count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kConfigDir)) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    Config c = loadConfig(entry.path().string());
    EXPECT_EQ(c.name + ".json", entry.path().filename().string()) << "a config's name is its file name";
    EXPECT_FALSE(expandVariants(c).empty());
    ++count;
  }
  EXPECT_GE(count, 6u);
}

TEST(ShippedConfigs, Table51HasTheThesisSixConfigurationsAt8x8Tiles) {
  Config c = loadConfig(kConfigDir + "/thesis-table-5-1.json");
  std::vector<Variant> v = expandVariants(c);
  ASSERT_EQ(namesOf(v), kTable51Names);
  struct Expected {
    bool lightCulling, aabb;
    NormalCulling normals;
  };
  const Expected expected[] = {{false, false, NormalCulling::Off},    {true, false, NormalCulling::Off},
                               {true, true, NormalCulling::Off},      {true, true, NormalCulling::Naive},
                               {true, true, NormalCulling::Improved}, {false, false, NormalCulling::Improved}};
  for (size_t i = 0; i < v.size(); ++i) {
    SCOPED_TRACE(v[i].name);
    EXPECT_EQ(v[i].params.tileSize, 8u);
    EXPECT_EQ(v[i].params.lightCulling, expected[i].lightCulling);
    EXPECT_EQ(v[i].params.aabb, expected[i].aabb);
    EXPECT_EQ(v[i].params.normalCulling, expected[i].normals);
    EXPECT_EQ(v[i].params.backend, RtBackend::Auto);
    EXPECT_EQ(v[i].params.resolution, (std::array<uint32_t, 2>{1920, 1080}));
    EXPECT_EQ(v[i].params.lightCount, std::optional<uint32_t>(10));
  }
  EXPECT_EQ(c.scene, "atrium");
  EXPECT_EQ(c.warmupFrames, 50u);
  EXPECT_EQ(c.measuredFrames, 300u);
}

TEST(ShippedConfigs, Table52SweepsTileSizesWithEverythingOn) {
  std::vector<Variant> v = expandVariants(loadConfig(kConfigDir + "/thesis-table-5-2.json"));
  ASSERT_EQ(namesOf(v), kTable52Names);
  const uint32_t tiles[] = {8, 16, 32};
  for (size_t i = 0; i < v.size(); ++i) {
    EXPECT_EQ(v[i].params.tileSize, tiles[i]);
    EXPECT_TRUE(v[i].params.lightCulling && v[i].params.aabb);
    EXPECT_EQ(v[i].params.normalCulling, NormalCulling::Improved);
  }
}

TEST(ShippedConfigs, ThesisIsBothTablesAndCiIsTheSameSweepSmall) {
  std::vector<std::string> both = kTable51Names;
  both.insert(both.end(), kTable52Names.begin(), kTable52Names.end());
  Config thesis = loadConfig(kConfigDir + "/thesis.json");
  Config ci = loadConfig(kConfigDir + "/ci.json");
  std::vector<Variant> tv = expandVariants(thesis), cv = expandVariants(ci);
  EXPECT_EQ(namesOf(tv), both);
  ASSERT_EQ(namesOf(cv), both);
  // Documented duplicate: the 5.1 row with everything on and the 5.2 8x8 row are one configuration.
  EXPECT_EQ(tv[4].params, tv[6].params);
  for (size_t i = 0; i < cv.size(); ++i) {
    VariantParams expected = tv[i].params;
    expected.resolution = {320, 180};
    EXPECT_EQ(cv[i].params, expected) << cv[i].name;
  }
  EXPECT_EQ(ci.warmupFrames, 2u);
  EXPECT_EQ(ci.measuredFrames, 5u);
}

TEST(ConfigScene, AHardCaseIsABuiltinSceneWithItsOwnCameraAndLightsButNoSceneParams) {
  Config c = parseText(R"({"name": "n", "scene": "grazing",
      "variants": [{"name": "a", "params": {"t_min": "scaled"}}]})");
  EXPECT_EQ(c.scene, "grazing");
  EXPECT_TRUE(c.sceneIsHardCase());
  EXPECT_FALSE(c.sceneIsBuiltin());
  EXPECT_EQ(c.variants[0].params.tMin, ShadowTMin::Scaled);
  EXPECT_FALSE(c.variants[0].params.lightCount.has_value());
  EXPECT_EQ(toJson(c)["scene"], "grazing");
  EXPECT_EQ(errorOfText(R"({"name": "n", "scene": "grazing", "scene_params": {"lights": 3}})"),
            R"(x.json: scene_params: applies only to the built-in "atrium" scene; remove it or set "scene": "atrium")");
  EXPECT_FALSE(parseText(R"({"name": "n", "scene": "atrium"})").sceneIsHardCase());
  EXPECT_FALSE(parseText(R"({"name": "n", "scene": "s.gltf"})").sceneIsHardCase());
}

TEST(ShippedConfigs, SponzaResolvesItsPathAgainstTheConfigFolderAndGivesCameraAndLights) {
  Config c = loadConfig(kConfigDir + "/thesis-sponza.json");
  std::filesystem::path expected = std::filesystem::path(kSourceDir) / "scenes/sponza/Sponza.gltf";
  EXPECT_EQ(c.scene, expected.lexically_normal().string());
  EXPECT_FALSE(c.sceneIsBuiltin());
  ASSERT_TRUE(c.lights.has_value());
  EXPECT_EQ(c.lights->size(), 10u);
  for (const Light& l : *c.lights) {
    EXPECT_TRUE(l.rangeFromEq41);
    EXPECT_FLOAT_EQ(l.range, float(rangeFromIntensity(l.intensity)));
  }
  EXPECT_TRUE(c.camera.explicitPose);
  std::vector<Variant> v = expandVariants(c);
  EXPECT_EQ(v.size(), 9u);
  for (const Variant& variant : v) EXPECT_FALSE(variant.params.lightCount || variant.params.triangleScale);
}

TEST(ShippedConfigs, ScalingVariesOneAxisAtATimeFromTheThesisSetup) {
  std::vector<Variant> v = expandVariants(loadConfig(kConfigDir + "/scaling.json"));
  ASSERT_EQ(v.size(), 6u);  // lights 10/100/1000, triangles x4/x16, 4K
  EXPECT_EQ(v.front().name, "lights=10");
  EXPECT_EQ(v[2].params.lightCount, std::optional<uint32_t>(1000));
  EXPECT_EQ(v[4].params.triangleScale, std::optional<double>(16.0));
  EXPECT_EQ(v.back().params.resolution, (std::array<uint32_t, 2>{3840, 2160}));
  for (const Variant& x : v) {
    EXPECT_EQ(x.params.tileSize, 8u);
    EXPECT_TRUE(x.params.lightCulling && x.params.aabb);
    EXPECT_EQ(x.params.normalCulling, NormalCulling::Improved);
    EXPECT_EQ(x.params.maxLightsPerTile, 32u);
  }
}

TEST(EmbeddedConfig, EqualsConfigsThesisJsonByteForByte) {
  EXPECT_EQ(embeddedDefaultConfigText(), readFile(kConfigDir + "/thesis.json"));
  std::vector<Variant> embedded = expandVariants(embeddedDefaultConfig());
  std::vector<Variant> file = expandVariants(loadConfig(kConfigDir + "/thesis.json"));
  ASSERT_EQ(namesOf(embedded), namesOf(file));
  for (size_t i = 0; i < file.size(); ++i) EXPECT_EQ(embedded[i].params, file[i].params);
}

TEST(EffectiveConfig, ReparsesToTheSameRunsForEveryShippedConfig) {
  for (const char* name : {"thesis", "ci", "thesis-sponza", "scaling", "thesis-table-5-1", "thesis-table-5-2"}) {
    SCOPED_TRACE(name);
    Config c = loadConfig(kConfigDir + "/" + name + ".json");
    nlohmann::json j = toJson(c);
    Config again = parseConfig(j, c.sourceName);
    std::vector<Variant> a = expandVariants(c), b = expandVariants(again);
    ASSERT_EQ(namesOf(a), namesOf(b));
    for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].params, b[i].params) << a[i].name;
    EXPECT_EQ(toJson(again), j) << "toJson is a fixed point";
    EXPECT_EQ(j["frames"]["measured"], c.measuredFrames);
  }
}

TEST(EffectiveConfig, FillsEveryParameterDefault) {
  Config c = parseText(R"({"name": "n", "variants": [{"name": "a", "params": {}}]})");
  nlohmann::json p = toJson(c)["variants"][0]["params"];
  for (const char* key :
       {"tile_size", "light_culling", "aabb", "normal_culling", "backend", "resolution", "world_pos", "range_test",
        "depth_slices", "t_min", "max_lights_per_tile", "light_count", "triangle_scale"})
    EXPECT_TRUE(p.contains(key)) << key;
  EXPECT_EQ(p["t_min"], "constant");  // the thesis's t_min
  // Built-in defaults: the thesis's best configuration (Tables 5.1 and 5.2).
  EXPECT_EQ(p["tile_size"], 8);
  EXPECT_EQ(p["normal_culling"], "improved");
  EXPECT_EQ(p["max_lights_per_tile"], 32);
}

TEST(Expansion, NamedVariantsComeFirstThenTheGridOnTopOfDefaults) {
  Config c = parseText(R"({"name": "n", "defaults": {"backend": "pipeline"},
      "variants": [{"name": "base", "params": {"tile_size": 32}}],
      "grid": {"tile_size": [8, 16], "normal_culling": ["naive", "improved"]}})");
  std::vector<Variant> v = expandVariants(c);
  EXPECT_EQ(namesOf(v), (std::vector<std::string>{
                            "base", "tile_size=8, normal_culling=naive", "tile_size=8, normal_culling=improved",
                            "tile_size=16, normal_culling=naive", "tile_size=16, normal_culling=improved"}));
  for (const Variant& x : v) EXPECT_EQ(x.params.backend, RtBackend::Pipeline);
  EXPECT_EQ(v[0].params.tileSize, 32u);
  EXPECT_EQ(v[3].params.tileSize, 16u);
  EXPECT_EQ(v[3].params.normalCulling, NormalCulling::Naive);
}

TEST(Expansion, NoVariantsAndNoGridIsOneDefaultRun) {
  std::vector<Variant> v = expandVariants(parseText(R"({"name": "n", "resolution": [640, 360]})"));
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0].name, "default");
  EXPECT_EQ(v[0].params.resolution, (std::array<uint32_t, 2>{640, 360}));
}

TEST(Expansion, SceneParamsSeedTheAtriumParametersAndVariantsOverrideThem) {
  Config c = parseText(R"({"name": "n", "scene_params": {"lights": 20, "triangle_scale": 2},
      "variants": [{"name": "a"}, {"name": "b", "params": {"light_count": 100}}]})");
  std::vector<Variant> v = expandVariants(c);
  EXPECT_EQ(v[0].params.lightCount, std::optional<uint32_t>(20));
  EXPECT_EQ(v[0].params.triangleScale, std::optional<double>(2.0));
  EXPECT_EQ(v[1].params.lightCount, std::optional<uint32_t>(100));
}

TEST(ConfigErrors, UnknownTopLevelKeySuggestsTheClosest) {
  EXPECT_EQ(errorOfText(R"({"name": "n", "grdi": {}})"), R"(x.json: unknown key "grdi" (did you mean "grid"?))");
}

TEST(ConfigErrors, UnknownKeyFarFromAnyListsTheAllowedKeys) {
  std::string e = errorOfText(R"({"name": "n", "effects": {"bloom": true}})");
  EXPECT_EQ(
      e, R"(x.json: effects: unknown key "bloom" (allowed: shadows, ambient_occlusion, indirect, environment_light))");
}

TEST(ConfigErrors, UnknownParamKeyNamesTheVariantPath) {
  std::string e = errorOfText(R"({"name": "n", "variants": [{"name": "a"}, {"name": "b"},
      {"name": "c", "params": {"tilesize": 8}}]})");
  EXPECT_EQ(e, R"(x.json: variants[2].params: unknown key "tilesize" (did you mean "tile_size"?))");
}

TEST(ConfigErrors, UnknownGridKeyNamesTheGrid) {
  EXPECT_EQ(errorOfText(R"({"name": "n", "grid": {"normal_cull": ["naive"]}})"),
            R"(x.json: grid: unknown key "normal_cull" (did you mean "normal_culling"?))");
}

TEST(ConfigErrors, WrongTypesNameTheKeyPathAndTheValue) {
  EXPECT_EQ(errorOfText(R"({"name": "n", "defaults": {"light_culling": "yes"}})"),
            R"(x.json: defaults.light_culling: expected true or false, got "yes")");
  EXPECT_EQ(errorOfText(R"({"name": "n", "frames": {"measured": 2.5}})"),
            "x.json: frames.measured: expected an integer, got 2.5");
  EXPECT_EQ(errorOfText(R"({"name": 3})"), "x.json: name: expected a string, got 3");
  EXPECT_EQ(errorOfText(R"({"name": "n", "grid": {"tile_size": 8}})"),
            "x.json: grid.tile_size: expected a non-empty list of values, got 8");
  EXPECT_EQ(errorOfText(R"({"name": "n", "resolution": 1920})"),
            "x.json: resolution: expected [width, height], got 1920");
}

TEST(ConfigErrors, OutOfRangeValuesSayWhatIsAllowed) {
  std::string e = errorOfText(R"({"name": "n", "variants": [{"name": "a"}, {"name": "b"},
      {"name": "c", "params": {"tile_size": 12}}]})");
  EXPECT_EQ(e, "x.json: variants[2].params.tile_size: 12 is not one of 8, 16, 32");
  EXPECT_EQ(errorOfText(R"({"name": "n", "resolution": [20000, 1080]})"),
            "x.json: resolution[0]: 20000 is out of range 1..16384");
  EXPECT_EQ(errorOfText(R"({"name": "n", "grid": {"normal_culling": ["naive", "best"]}})"),
            R"(x.json: grid.normal_culling[1]: "best" is not one of "off", "naive", "improved", "geometric")");
  EXPECT_EQ(errorOfText(R"({"name": "n", "defaults": {"max_lights_per_tile": 48}})"),
            "x.json: defaults.max_lights_per_tile: 48 is not a multiple of 32");
  EXPECT_EQ(errorOfText(R"({"name": "n", "defaults": {"depth_slices": 1}})"),
            "x.json: defaults.depth_slices: 1 is not allowed: use 0 (off) or 2..32 slices");
  EXPECT_EQ(errorOfText(R"({"name": "n", "defaults": {"t_min": "adaptive"}})"),
            R"(x.json: defaults.t_min: "adaptive" is not one of "constant", "scaled")");
  EXPECT_EQ(errorOfText(R"({"name": "n", "scene_params": {"triangle_scale": 100}})"),
            "x.json: scene_params.triangle_scale: 100 is out of range [0.25, 64.0]");
  EXPECT_EQ(errorOfText(R"({"name": "n", "scene_params": {"light_range": [2, 1]}})"),
            "x.json: scene_params.light_range: [2,1] is not a range; use [min, max] with 0 < min <= max < 1e6");
}

TEST(Config, LightRangeGivesEveryAtriumLightARangeInsideIt) {
  const Config c = parseText(R"({"name": "n", "scene_params": {"lights": 50, "light_range": [0.5, 2]}})");
  EXPECT_EQ(c.sceneParams.lightRangeMin, 0.5);
  EXPECT_EQ(c.sceneParams.lightRangeMax, 2.0);
  const Scene ranged = makeAtrium(c.sceneParams);
  AtriumParams plainParams = c.sceneParams;
  plainParams.lightRangeMin = plainParams.lightRangeMax = 0.0;
  const Scene plain = makeAtrium(plainParams);
  ASSERT_EQ(ranged.lights.size(), 50u);
  for (size_t i = 0; i < ranged.lights.size(); ++i) {
    EXPECT_GE(ranged.lights[i].range, 0.5f);
    EXPECT_LE(ranged.lights[i].range, 2.0f);
    EXPECT_FALSE(ranged.lights[i].rangeFromEq41);
    EXPECT_EQ(ranged.lights[i].position, plain.lights[i].position);  // only the ranges change
    EXPECT_EQ(ranged.lights[i].intensity, plain.lights[i].intensity);
  }
  EXPECT_EQ(toJson(c)["scene_params"]["light_range"], nlohmann::json({0.5, 2.0}));
}

TEST(ConfigErrors, DuplicateNamesAreRefused) {
  EXPECT_EQ(errorOfText(R"({"name": "n", "variants": [{"name": "a"}, {"name": "a"}]})"),
            R"(x.json: variants[1].name: the name "a" is used twice (also by variants[0]); names must be unique)");
  EXPECT_EQ(errorOfText(R"({"name": "n", "variants": [{"name": "tile_size=8"}], "grid": {"tile_size": [8, 16]}})"),
            R"(x.json: grid: the name "tile_size=8" is used twice (also by variants[0]); names must be unique)");
  EXPECT_EQ(errorOfText(R"({"name": "n", "grid": {"tile_size": [8, 16, 8]}})"),
            "x.json: grid.tile_size[2]: 8 is already in the list at [0]");
}

TEST(ConfigErrors, SceneSpecificParametersAreRefusedForGltfScenes) {
  EXPECT_EQ(errorOfText(R"({"name": "n", "scene": "s.gltf", "scene_params": {"lights": 3}})"),
            R"(x.json: scene_params: applies only to the built-in "atrium" scene; remove it or set "scene": "atrium")");
  std::string e =
      errorOfText(R"({"name": "n", "scene": "s.gltf", "variants": [{"name": "a", "params": {"triangle_scale": 2}}]})");
  EXPECT_EQ(e.rfind("x.json: variants[0].params: triangle_scale applies only to the built-in \"atrium\" scene", 0), 0u)
      << e;
  // light_count works on any scene (automatic lights, app/auto_scene.h), but not beside a list.
  EXPECT_NO_THROW(
      parseText(R"({"name": "n", "scene": "s.gltf", "variants": [{"name": "a", "params": {"light_count": 3}}]})"));
  e = errorOfText(
      R"({"name": "n", "scene": "s.gltf", "lights": [], "variants": [{"name": "a", "params": {"light_count": 3}}]})");
  EXPECT_NE(e.find("light_count cannot be combined with the config's explicit \"lights\" list"), std::string::npos)
      << e;
  EXPECT_EQ(
      errorOfText(R"({"name": "n", "scene": "sponza"})"),
      R"(x.json: scene: "sponza" is neither a built-in scene (atrium, plane, depth-step, cube, tiny-triangles, grazing, grazing-far, thin-gap, degenerate, open-occluder, far-origin, far-planes, microbench-262144, microbench-144, microbench-dense, microbench-tiny) nor a .gltf/.glb path)");
}

TEST(ConfigErrors, StructuralMistakesNameTheField) {
  EXPECT_EQ(errorOfText(R"({"scene": "atrium"})"),
            R"(x.json: missing "name"; every config needs one, e.g. "name": "my-sweep")");
  EXPECT_EQ(errorOfText(R"({"name": "n", "resolution": [640, 360], "defaults": {"resolution": [320, 180]}})"),
            R"(x.json: defaults.resolution: is also given at the top level as "resolution"; keep one)");
  EXPECT_EQ(errorOfText(R"({"name": "n", "lights": [{"type": "directional", "position": [0, 1, 0]}]})"),
            "x.json: lights[0].position: does not apply to a directional light; remove it");
  EXPECT_EQ(errorOfText(R"({"name": "n", "lights": [{"type": "spot", "position": [0, 1, 0]}]})"),
            R"(x.json: lights[0]: a spot light needs "direction")");
  EXPECT_EQ(errorOfText(R"({"name": "n", "camera": {"index": 0, "position": [0, 0, 0]}})")
                .rfind("x.json: camera: give either", 0),
            0u);
  EXPECT_EQ(errorOfText(R"({"name": "my sweep"})"),
            R"(x.json: name: "my sweep" may use only letters, digits, '.', '_' and '-' (it names output files))");
}

// A file named by the process and the test: ctest -j runs each test in its own process, started
// together, so a name from anything shared between them (gtest's random seed is the clock's
// millisecond) lets two tests write and remove one file.
class TempFile {
 public:
  explicit TempFile(const std::string& text)
      : path_(std::filesystem::temp_directory_path() /
              ("hb_config_test_" + std::to_string(::getpid()) + "_" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name() + "_" + std::to_string(counter_++) +
               ".json")) {
    std::ofstream(path_, std::ios::binary) << text;
  }
  ~TempFile() { std::filesystem::remove(path_); }
  std::string path() const { return path_.string(); }

 private:
  static inline int counter_ = 0;
  std::filesystem::path path_;
};

TEST(ConfigErrors, MalformedJsonNamesFileLineAndColumn) {
  TempFile f("{\n  \"name\": \"n\",\n  \"frames\": {\"warmup\": }\n}\n");
  std::string e = inputErrorOf([&] { loadConfig(f.path()); });
  // Line 3 is `  "frames": {"warmup": }`: the '}' that is not a value is its 24th character.
  EXPECT_EQ(e.rfind(f.path() + ":3:24: malformed JSON: syntax error", 0), 0u) << e;
}

TEST(ConfigErrors, AKeyGivenTwiceIsRefusedWithItsPath) {
  TempFile f(R"({"name": "n", "variants": [{"name": "a", "params": {"aabb": true, "aabb": false}}]})");
  EXPECT_EQ(inputErrorOf([&] { loadConfig(f.path()); }),
            f.path() + R"(: variants[0].params: key "aabb" is given twice; keep one)");
}

TEST(ConfigErrors, MissingFileSaysSo) {
  std::string e = inputErrorOf([] { loadConfig("/nonexistent/x.json"); });
  EXPECT_EQ(e.rfind("/nonexistent/x.json: no such file; give the path of a config JSON file", 0), 0u) << e;
}

TEST(ConfigLoading, CommentsAreAllowedInFiles) {
  TempFile f("// a sweep\n{\"name\": \"n\", /* inline */ \"grid\": {\"tile_size\": [8, 16]}}\n");
  EXPECT_EQ(expandVariants(loadConfig(f.path())).size(), 2u);
}

TEST(SetOverride, AcceptsJsonValuesBareWordsAndWxH) {
  VariantParams p;
  applySetOverride(p, "tile_size=32");
  applySetOverride(p, "normal_culling=naive");
  applySetOverride(p, "light_culling=false");
  applySetOverride(p, "resolution=640x360");
  applySetOverride(p, "light_count=7");
  EXPECT_EQ(p.tileSize, 32u);
  EXPECT_EQ(p.normalCulling, NormalCulling::Naive);
  EXPECT_FALSE(p.lightCulling);
  EXPECT_EQ(p.resolution, (std::array<uint32_t, 2>{640, 360}));
  EXPECT_EQ(p.lightCount, std::optional<uint32_t>(7));
  applySetOverride(p, "resolution=[320,180]");
  EXPECT_EQ(p.resolution, (std::array<uint32_t, 2>{320, 180}));
}

TEST(SetOverride, BadOverridesGiveTheConfigMessages) {
  VariantParams p;
  auto err = [&](const std::string& kv) { return inputErrorOf([&] { applySetOverride(p, kv); }); };
  EXPECT_EQ(err("tile_size=12"), "--set tile_size=12: tile_size: 12 is not one of 8, 16, 32");
  EXPECT_EQ(err("tilesize=8"), R"(--set tilesize=8: unknown key "tilesize" (did you mean "tile_size"?))");
  EXPECT_EQ(err("aabb=maybe"), R"(--set aabb=maybe: aabb: expected true or false, got "maybe")");
  EXPECT_EQ(err("resolution=1920x"),
            R"(--set resolution=1920x: resolution: expected WIDTHxHEIGHT (e.g. 1920x1080) or [w, h], got "1920x")");
  EXPECT_EQ(err("tile_size").rfind("--set tile_size: expected key=value", 0), 0u);
  EXPECT_EQ(p, VariantParams{}) << "a refused override changes nothing";
}

TEST(SetOverride, SceneCheckRefusesAtriumParametersOnGltf) {
  Config c = parseText(R"({"name": "n", "scene": "s.gltf"})");
  VariantParams p = expandVariants(c)[0].params;
  applySetOverride(p, "triangle_scale=4");
  std::string e = inputErrorOf([&] { checkParamsFitScene(c, p, "--set triangle_scale=4"); });
  EXPECT_EQ(e.rfind("--set triangle_scale=4: triangle_scale applies only to the built-in \"atrium\" scene", 0), 0u)
      << e;
}

TEST(CpuLowering, CapsResolutionAndFramesKeepsNamesAndAddsANote) {
  Config c = lowerForCpuDevice(loadConfig(kConfigDir + "/scaling.json"));
  std::vector<Variant> v = expandVariants(c);
  EXPECT_EQ(v.size(), 6u);
  EXPECT_EQ(v.back().name, "resolution=3840x2160");
  // 1920x1080 / 4 and 3840x2160 / 8 are both exactly 480x270.
  for (const Variant& x : v) EXPECT_EQ(x.params.resolution, (std::array<uint32_t, 2>{480, 270})) << x.name;
  EXPECT_EQ(c.warmupFrames, 2u);
  EXPECT_EQ(c.measuredFrames, 5u);
  ASSERT_EQ(c.notes.size(), 1u);
  EXPECT_NE(c.notes[0].find("1920x1080 -> 480x270"), std::string::npos) << c.notes[0];
  EXPECT_NE(c.notes[0].find("3840x2160 -> 480x270"), std::string::npos) << c.notes[0];
  EXPECT_EQ(toJson(c)["notes"][0], c.notes[0]);
}

TEST(CpuLowering, CapsAmbientOcclusionSizesInEveryVariantAndNotesThem) {
  Config c = lowerForCpuDevice(loadConfig(kConfigDir + "/layered-depth-maps.json"));
  for (const Variant& v : expandVariants(c)) {
    const nlohmann::json& ao = v.params.effects["ambient_occlusion"];
    if (ao.is_object()) {
      EXPECT_LE(ao.value("directions", 0), 64) << v.name;
      EXPECT_LE(ao.value("ldm_resolution", 0), 128) << v.name;
      EXPECT_LE(ao.value("samples", 0), 256) << v.name;
      EXPECT_LE(ao.value("steps", 0), 32) << v.name;
    }
    const nlohmann::json ind = v.params.effects.value("indirect", nlohmann::json());
    if (ind.is_object()) {
      EXPECT_LE(ind.value("directions", 0), 64) << v.name;
      EXPECT_LE(ind.value("ldm_resolution", 0), 128) << v.name;
      EXPECT_LE(ind.value("photons", 0), 4) << v.name;
    }
  }
  ASSERT_EQ(c.notes.size(), 1u);
  EXPECT_NE(c.notes[0].find("ambient_occlusion directions 512 -> 64"), std::string::npos) << c.notes[0];
  EXPECT_NE(c.notes[0].find("ambient_occlusion ldm_resolution 256 -> 128"), std::string::npos) << c.notes[0];
  EXPECT_NE(c.notes[0].find("indirect photons 32 -> 4"), std::string::npos) << c.notes[0];
}

TEST(CpuLowering, LeavesSmallConfigsAloneButStillNotesTheDevice) {
  Config ci = loadConfig(kConfigDir + "/ci.json");
  Config lowered = lowerForCpuDevice(ci);
  std::vector<Variant> a = expandVariants(ci), b = expandVariants(lowered);
  for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].params, b[i].params);
  ASSERT_EQ(lowered.notes.size(), 1u);
  EXPECT_NE(lowered.notes[0].find("already fits"), std::string::npos);
}

TEST(EffectiveConfig, PrintsFloatsAsWrittenAndLightsInFull) {
  Config c = loadConfig(kConfigDir + "/thesis-sponza.json");
  nlohmann::json j = toJson(c);
  EXPECT_EQ(j["camera"]["position"], nlohmann::json({-1.0, 1.8, -0.35}));
  EXPECT_EQ(j["lights"][1]["intensity"], 0.6);
  // The shortest decimal that reads back to the same float: exact after the round trip.
  EXPECT_EQ(float(j["lights"][1]["range"].get<double>()), (*c.lights)[1].range);
  EXPECT_EQ(j["scene"], c.scene);
}

TEST(ConfigCamera, ExplicitPoseLooksFromPositionToTarget) {
  Config c = parseText(R"({"name": "n", "camera": {"position": [1, 2, 3], "target": [1, 2, -7], "yfov_deg": 90}})");
  Camera cam = cameraFromSpec(c.camera);
  // lookAt maps the eye to the origin and the target onto -z at its distance (10); float round-off
  // of a translation by values <= 10 is below 10 * 2^-23 ~ 1.2e-6, so 1e-5 is a safe bound.
  glm::vec4 eye = cam.view * glm::vec4(1, 2, 3, 1), target = cam.view * glm::vec4(1, 2, -7, 1);
  EXPECT_NEAR(glm::length(glm::vec3(eye)), 0.0f, 1e-5f);
  EXPECT_NEAR(target.z, -10.0f, 1e-5f);
  EXPECT_NEAR(cam.yfov, glm::radians(90.0f), 1e-7f);
}

// Found by fuzz_config (tests/fuzz/corpus/config/float-overflow.json): a light's numbers beyond a
// float became inf (a direction then NaN), and a direction with a component of 2e31 normalised to
// zero in float (its length overflowed).
TEST(ConfigErrors, LightNumbersBeyondAFloatAreNamedAndHugeDirectionsStayUnit) {
  EXPECT_EQ(errorOfText(R"({"name": "n", "lights": [{"type": "directional", "direction": [0.3, -1, 2.1e307]}]})"),
            "x.json: lights[0].direction[2]: 2.1e+307 is out of range for a float; give a magnitude below 3.4e38");
  EXPECT_EQ(errorOfText(R"({"name": "n", "lights": [{"type": "point", "position": [0, 0, 0], "intensity": 1e39}]})"),
            "x.json: lights[0].intensity: 1e+39 is out of range for a float; give a magnitude below 3.4e38");
  Config c = parseText(R"({"name": "n", "lights": [{"type": "directional", "direction": [0.3, -1, 2.07e31]}]})");
  ASSERT_TRUE(c.lights.has_value());
  EXPECT_EQ((*c.lights)[0].direction.z, 1.0f);
  EXPECT_EQ(parseConfig(toJson(c), "x.json").lights->at(0).direction.z, 1.0f);  // and reads back
}

// Numbers a float holds, 6e38 m apart: lookAt's float view was NaN (fuzz_config's camera check).
TEST(ConfigErrors, ACameraPoseWithoutAViewIsNamed) {
  EXPECT_EQ(errorOfText(R"({"name": "n", "camera": {"position": [-3e38, 0, 0], "target": [3e38, 0, 0]}})"),
            "x.json: camera: position, target and up give no view in float; give them in metres "
            "below 1e19");
}

TEST(ConfigErrors, EveryMessageIsOneLine) {
  for (const char* bad :
       {R"({"name": "n", "grdi": 1})", R"({"name": "n", "defaults": {"tile_size": "big"}})",
        R"({"name": "n", "lights": [{"type": "spot", "position": [0, 0, 0], "direction": [0, 0, 0]}]})", R"([1, 2])"}) {
    std::string e = errorOfText(bad);
    EXPECT_FALSE(e.empty()) << bad;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
}

TEST(ConfigCamera, AutoIsAcceptedAndWrittenBackAndAnythingElseIsNamed) {
  Config c = parseText(R"({"name": "n", "scene": "s.gltf", "camera": "auto"})");
  EXPECT_TRUE(c.camera.autoFrame);
  EXPECT_FALSE(c.camera.explicitPose);
  EXPECT_EQ(toJson(c)["camera"], "auto");
  EXPECT_FALSE(parseText(R"({"name": "n", "scene": "s.gltf"})").camera.autoFrame);
  EXPECT_EQ(
      errorOfText(R"({"name": "n", "camera": "front"})"),
      R"(x.json: camera: "front" is not "auto"; give "auto" (frame the scene's bounds), {"index": N} or {"position", "target"})");
}

// A sweep's --set of some of an effect's settings is laid over the config's effects and over each
// variant's own value: the keys it leaves out keep theirs (docs/usage.md "Precedence").
TEST(SetOverride, AnEffectSetKeepsTheSettingsOfTheConfigAndOfEachVariantThatItLeavesOut) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("hb-effect-set-config-" + std::to_string(::getpid()) + ".json");
  {
    std::ofstream f(path);
    f << R"({"name": "x", "scene": "atrium", "resolution": [64, 36],
             "effects": {"indirect": {"directions": 128, "photons": 4}},
             "variants": [{"name": "ldm", "params": {}},
                          {"name": "rt", "params": {"effects": {"indirect": {"method": "raytraced"}}}},
                          {"name": "off", "params": {"effects": {"indirect": false}}}]})";
  }
  const Config c = loadConfigWith(path.string(), ConfigOverrides{.sets = {R"(effects.indirect={"bounces":2})"}});
  std::filesystem::remove(path);
  EXPECT_EQ(c.effects["indirect"], (nlohmann::json{{"directions", 128}, {"photons", 4}, {"bounces", 2}}));
  ASSERT_EQ(c.variants.size(), 3u);
  EXPECT_FALSE(c.variants[0].params.effects.is_object() && c.variants[0].params.effects.contains("indirect"));
  EXPECT_EQ(c.variants[1].params.effects["indirect"], (nlohmann::json{{"method", "raytraced"}, {"bounces", 2}}));
  EXPECT_EQ(c.variants[2].params.effects["indirect"], (nlohmann::json{{"bounces", 2}}));
}

}  // namespace
}  // namespace hb
