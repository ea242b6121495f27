// End-to-end: the effects a glTF scene calls for (scenes[0].extras.effects), a config's effects
// and --set, in that order of precedence, decide the frame; render.json says which effects ran,
// from which source, and why a pass was skipped. Renders are 64x36 on the exported "plane" case.
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tool_process.h"

namespace {

namespace fs = std::filesystem;
using hb::testing::readFile;
using hb::testing::RunResult;
using hb::testing::writeFile;
using nlohmann::json;

class EffectsCli : public hb::testing::ToolTest {
 protected:
  // The "plane" hard case exported to glTF, with `effects` as scenes[0].extras.effects.
  fs::path planeGltf(const json& effects, const std::string& name) {
    const fs::path plain = dir / "plane.gltf";
    if (!fs::exists(plain)) {
      const RunResult ex = run({"scene", "export", "plane", plain.string()});
      EXPECT_EQ(ex.exitCode, 0) << ex.err;
    }
    json doc = json::parse(readFile(plain));
    doc["scenes"][0]["extras"]["effects"] = effects;
    const fs::path p = dir / name;
    writeFile(p, doc.dump(1));
    return p;
  }

  json render(const std::vector<std::string>& extra, const std::string& outName) {
    std::vector<std::string> args{"render", "--size", "64x36"};
    args.insert(args.end(), extra.begin(), extra.end());
    args.push_back("--out");
    args.push_back((dir / outName).string());
    const RunResult r = run(args);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return json::parse(readFile(dir / outName / "render.json"), nullptr, false);
  }

  static bool ran(const json& report, const std::string& pass) {
    const json& p = report["passes_run"];
    return std::find(p.begin(), p.end(), pass) != p.end();
  }
};

TEST_F(EffectsCli, SceneTurnsShadowsOffConfigTurnsThemOnSetWinsOverBoth) {
  const fs::path gltf = planeGltf({{"shadows", false}}, "no-shadows.gltf");

  // The scene alone: no shadow pass, no BLAS/TLAS, and the reason names the scene.
  const json byScene = render({"--scene", gltf.string()}, "scene");
  ASSERT_FALSE(byScene.is_discarded());
  EXPECT_FALSE(ran(byScene, "shadows"));
  EXPECT_TRUE(ran(byScene, "depth_prepass"));
  EXPECT_FALSE(byScene.contains("acceleration_structures"));
  EXPECT_EQ(byScene["effects"]["shadows"]["source"], "scene");
  EXPECT_EQ(byScene["effects"]["shadows"]["runs"], false);
  EXPECT_EQ(byScene["passes_skipped"]["shadows"], "effects.shadows is off (scene: " + gltf.string() + ")");

  // A config that turns them back on wins over the scene.
  const fs::path config = dir / "on.json";
  writeFile(config, json{{"name", "on"}, {"scene", gltf.string()}, {"effects", {{"shadows", true}}}}.dump());
  const json byConfig = render({config.string()}, "config");
  ASSERT_FALSE(byConfig.is_discarded());
  EXPECT_TRUE(ran(byConfig, "shadows"));
  EXPECT_TRUE(byConfig.contains("acceleration_structures"));
  EXPECT_EQ(byConfig["effects"]["shadows"]["source"], "config");
  EXPECT_EQ(byConfig["effects"]["shadows"]["runs"], true);

  // --set wins over both.
  const json bySet = render({config.string(), "--set", "shadows=false"}, "set");
  ASSERT_FALSE(bySet.is_discarded());
  EXPECT_FALSE(ran(bySet, "shadows"));
  EXPECT_FALSE(bySet.contains("acceleration_structures"));
  EXPECT_EQ(bySet["effects"]["shadows"]["source"], "--set");
  EXPECT_EQ(bySet["passes_skipped"]["shadows"], "effects.shadows is off (--set: --set shadows=false)");
}

TEST_F(EffectsCli, UnknownEffectOrBadValueInExtrasIsExit2WithOneLineNamingFileAndKeyPath) {
  struct Case {
    json effects;
    std::string keyPath;
  };
  for (const Case& c : {Case{{{"bloom", true}}, "scenes[0].extras.effects: unknown key \"bloom\""},
                        Case{{{"shadows", {{"method", "ldm"}}}}, "scenes[0].extras.effects.shadows"},
                        Case{json::array({"shadows"}), "scenes[0].extras.effects"}}) {
    SCOPED_TRACE(c.effects.dump());
    const fs::path gltf = planeGltf(c.effects, "bad.gltf");
    const RunResult r = run({"render", "--scene", gltf.string(), "--size", "64x36", "--out", (dir / "bad").string()});
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find(gltf.string() + ": " + c.keyPath), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "bad" / "render.json"));
  }
}

TEST_F(EffectsCli, SceneInfoShowsWhatTheSceneCallsFor) {
  const fs::path gltf = planeGltf({{"shadows", false}}, "no-shadows.gltf");
  const RunResult info = run({"scene", "info", gltf.string(), "--json"});
  ASSERT_EQ(info.exitCode, 0) << info.err;
  const json j = json::parse(info.out, nullptr, false);
  ASSERT_FALSE(j.is_discarded());
  EXPECT_EQ(j["effects"], (json{{"shadows", false}}));
}

// A config's environment (its image relative to the config) lights the frame through the
// environment_light effect: render.json carries its settings, the environment as resolved and its
// errors against the same directions ray traced and the reference, with the images beside; a
// missing image is exit 2 in one line naming the key, and nothing is written.
TEST_F(EffectsCli, AConfigsEnvironmentLightsTheFrameAndAMissingImageIsExit2) {
  fs::create_directories(dir / "cfg");
  fs::copy_file(fs::path(HYBRIDBENCH_SOURCE_DIR) / "scenes/environments/sky.hdr", dir / "cfg" / "sky.hdr");
  const fs::path gltf = planeGltf({{"shadows", true}}, "plane-env.gltf");
  json cfg = {{"name", "env"},
              {"scene", gltf.string()},
              {"environment", {{"image", "sky.hdr"}, {"rotation", 30}}},
              {"effects", {{"environment_light", {{"method", "ldm"}, {"directions", 8}, {"ldm_resolution", 32}}}}}};
  writeFile(dir / "cfg" / "env.json", cfg.dump(1));
  const json report = render({(dir / "cfg" / "env.json").string()}, "env");
  ASSERT_TRUE(report.is_object());
  EXPECT_TRUE(ran(report, "environment_ldm_build"));
  EXPECT_TRUE(ran(report, "environment_light"));
  const json& e = report["environment_light"];
  EXPECT_EQ(e["method"], "ldm");
  EXPECT_EQ(e["environment"]["image"], (dir / "cfg" / "sky.hdr").lexically_normal().string());
  EXPECT_EQ(e["environment"]["image_size"], json::array({128, 64}));
  EXPECT_TRUE(e["vs_raytraced"]["rel_mse"].is_number()) << e.dump();
  EXPECT_TRUE(e["vs_reference"]["rel_mse"].is_number()) << e.dump();
  for (const char* png : {"environment.png", "environment_raytraced.png", "environment_reference.png",
                          "environment_error_vs_reference.png"})
    EXPECT_TRUE(fs::exists(dir / "env" / png)) << png;

  cfg["environment"]["image"] = "nowhere.hdr";
  writeFile(dir / "cfg" / "missing.json", cfg.dump(1));
  const RunResult r =
      run({"render", (dir / "cfg" / "missing.json").string(), "--size", "64x36", "--out", (dir / "missing").string()});
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("environment.image: '"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("nowhere.hdr' does not exist"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "missing" / "render.json"));
}

}  // namespace
