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

using namespace hb::testing;

class EffectsCli : public ToolTest {
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

// A --set that names some of an effect's settings changes only those: the Cornell box's own
// "indirect": {"directions": 128} stays 128 under --set effects.indirect={"bounces":2,...}, so a
// comparison of 1 bounce against 2 changes one setting (docs/usage.md "Precedence"). Bounces with
// method ldm need sbuffer lists: the tool takes them where no layer chose a list, and says so;
// a list the user chose is refused in one line naming the --set, before anything is written.
TEST_F(EffectsCli, ASetOfSomeSettingsKeepsTheScenesOthersAndBouncesTakeSbufferUnlessAListWasChosen) {
  const std::string cornell = (fs::path(HYBRIDBENCH_SOURCE_DIR) / "scenes/cornell-box.gltf").string();
  // Small photons and maps keep lavapipe's run short; they are --set, so they do not touch directions.
  const std::string set = R"(effects.indirect={"bounces":2,"photons":2,"ldm_resolution":16})";
  const RunResult r =
      run({"render", "--scene", cornell, "--size", "32x32", "--set", set, "--out", (dir / "bounces").string()});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const json report = json::parse(readFile(dir / "bounces" / "render.json"), nullptr, false);
  ASSERT_FALSE(report.is_discarded());
  const json& indirect = report["effects"]["indirect"];
  EXPECT_EQ(indirect["runs"], true);
  EXPECT_EQ(indirect["value"]["directions"], 128) << indirect.dump();  // the scene's, kept
  EXPECT_EQ(indirect["value"]["method"], "ldm") << indirect.dump();
  EXPECT_EQ(indirect["value"]["bounces"], 2) << indirect.dump();
  EXPECT_EQ(indirect["value"]["ldm_list"], "sbuffer") << indirect.dump();
  EXPECT_EQ(indirect["settings_from"]["directions"], cornell) << indirect.dump();
  EXPECT_EQ(indirect["settings_from"]["bounces"], "--set " + set) << indirect.dump();
  EXPECT_EQ(indirect["settings_from"]["ldm_list"], "chosen by the tool") << indirect.dump();
  ASSERT_EQ(indirect["notes"].size(), 1u) << indirect.dump();
  EXPECT_NE(r.out.find("note: effects.indirect.ldm_list: \"sbuffer\", chosen by the tool"), std::string::npos) << r.out;

  // The user chose another list: refused, one line naming that --set and the fix; nothing written.
  const std::string chosen = R"(effects.indirect={"bounces":2,"ldm_list":"max64"})";
  const RunResult refused =
      run({"render", "--scene", cornell, "--size", "32x32", "--set", chosen, "--out", (dir / "refused").string()});
  EXPECT_EQ(refused.exitCode, 2) << refused.err;
  EXPECT_EQ(std::count(refused.err.begin(), refused.err.end(), '\n'), 1) << refused.err;
  EXPECT_NE(refused.err.find("ldm_list is \"max64\" (--set " + chosen + ")"), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("set \"ldm_list\": \"sbuffer\""), std::string::npos) << refused.err;
  EXPECT_FALSE(fs::exists(dir / "refused" / "render.json"));
}

}  // namespace
