// Bring your own glTF (issue #18): a scene with no camera and no lights renders and sweeps with
// automatic ones, says so, and records where its camera and lights came from; a scene with its own
// is unchanged. End to end: the built tool on the device present (lavapipe on CI).
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "base/image_io.h"
#include "tool_process.h"

namespace {

using namespace hb::testing;

class AutoScene : public ToolTest {
 protected:
  // The built-in cube exported (its own camera and light), and the same file with every camera
  // and light removed: what most real glTF assets look like.
  void SetUp() override {
    ToolTest::SetUp();
    own = dir / "cube.gltf";
    bare = dir / "bare.gltf";
    const RunResult ex = run({"scene", "export", "cube", own.string()});
    ASSERT_EQ(ex.exitCode, 0) << ex.err;
    json doc = json::parse(readFile(own));
    json nodes = json::array();
    json roots = json::array();
    for (const json& node : doc["nodes"])
      if (node.contains("mesh")) {
        roots.push_back(nodes.size());
        nodes.push_back(node);
      }
    ASSERT_FALSE(nodes.empty());
    doc["nodes"] = nodes;
    doc["scenes"][0]["nodes"] = roots;
    for (const char* key : {"cameras", "extensions", "extensionsUsed"}) doc.erase(key);
    writeFile(bare, doc.dump(1));
  }

  json renderJson(const std::vector<std::string>& extra, const fs::path& out, RunResult& r) {
    std::vector<std::string> args{"render", "--size", "64x36", "--out", out.string()};
    args.insert(args.end(), extra.begin(), extra.end());
    r = run(args);
    if (r.exitCode != 0) return json();
    return json::parse(readFile(out / "render.json"), nullptr, false);
  }

  fs::path own, bare;
};

TEST_F(AutoScene, AGltfWithNoCameraAndNoLightsRendersWithAutomaticOnesAndSaysSo) {
  RunResult r;
  const json j = renderJson({"--scene", bare.string()}, dir / "bare-out", r);
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  ASSERT_TRUE(j.is_object());
  // The cube's centre is inside the cube, and a free point beside it is in the open: outside.
  EXPECT_NE(r.err.find("is open ("), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("so an automatic camera outside at"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("has no lights: 10 automatic point lights"), std::string::npos) << r.err;
  EXPECT_EQ(j["camera"]["source"], "auto");
  EXPECT_EQ(j["lights"]["source"], "auto");
  EXPECT_EQ(j["lights"]["count"], 10);
  // Shadows are traced: the shadow pass ran and traced rays.
  EXPECT_GT(j["rays"].value("traced", uint64_t(0)), 0u) << j["rays"].dump();
  // A non-empty image, lit where the scene is. The cube's 8 m ground square, projected through the
  // automatic camera (auto_scene.h: centre (0, 0.75, 0), r = 5.72, eye at 2r from azimuth 30° and
  // elevation 20°, yfov 60°) by hand, covers 9.94 % of a 16:9 frame: 229 of 64x36 pixels, the
  // cube inside that outline. Its outline crosses about 60 pixels, each of which may fall either
  // way, so at least 229 - 60 = 169 pixels must be lit (brighter than black by more than 8/255 per
  // channel on average, well above the tone mapper's rounding).
  const hb::ImageRGBA8 color = hb::readPng(dir / "bare-out" / "color.png");
  size_t lit = 0;
  for (size_t i = 0; i < size_t(color.width) * color.height; ++i)
    lit += color.px[4 * i] + color.px[4 * i + 1] + color.px[4 * i + 2] > 24;
  EXPECT_GE(lit, 169u) << lit << " lit pixels";
}

// The atrium exported bare is an interior: the centre of its bounds is enclosed, so the automatic
// camera stands inside, and sees nothing but the building.
TEST_F(AutoScene, AnInteriorExportedBareIsSeenFromInside) {
  const fs::path atrium = dir / "atrium-bare.glb";
  const RunResult ex = run({"scene", "export", "atrium", atrium.string(), "--no-camera", "--no-lights"});
  ASSERT_EQ(ex.exitCode, 0) << ex.err;
  RunResult r;
  const json j = renderJson({"--scene", atrium.string()}, dir / "atrium-out", r);
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  EXPECT_EQ(j["camera"]["source"], "auto");
  // The centre of the bounds, (0, 6, 0), is free and enclosed; the eye stands 1.7 m above the
  // courtyard floor (y = 0) below it and looks level (auto_scene.h).
  const std::string inside = "the centre of its bounds is enclosed";
  ASSERT_NE(r.err.find(inside), std::string::npos) << r.err;
  const std::string at = "an automatic camera inside at (0, 1.7, 0) looking along (";
  const size_t along = r.err.find(at);
  ASSERT_NE(along, std::string::npos) << r.err;
  const std::string direction = r.err.substr(along + at.size(), r.err.find(')', along + at.size()) - along - at.size());
  EXPECT_EQ(direction.substr(direction.find(", ") + 2, 3), "0, ") << direction;  // level: y = 0
  EXPECT_NE(r.err.find("the longest free level direction ("), std::string::npos) << r.err;
  // No pixel sees the background. A ray from the eye that leaves the building must first reach
  // the height of the courtyard beams' tops, 11.3 m, over the open courtyard (|x| < 14.5 m,
  // |z| < 3.7 m): everywhere else at that height are the walls, the beams and the gallery roofs
  // (src/scene/atrium.cpp). The farthest such point from the eye, (±14.5, 11.3, ±3.7), is 9.6 m up
  // at 14.96 m: 32.7° above level, the least a ray out can rise. A level view of yfov 60° rises at
  // most 30° (its top edge), so every pixel meets the building. The depth image paints cleared
  // depth (nothing drawn) (16, 24, 88) and every drawn pixel grey (r = g = b).
  const hb::ImageRGBA8 depth = hb::readPng(dir / "atrium-out" / "depth.png");
  size_t background = 0;
  for (size_t i = 0; i < size_t(depth.width) * depth.height; ++i) background += depth.px[4 * i] != depth.px[4 * i + 2];
  EXPECT_EQ(background, 0u) << "of " << depth.width * depth.height << " pixels";
}

// `scene export --no-camera --no-lights` writes such a file from any built-in.
TEST_F(AutoScene, ExportCanLeaveTheCameraAndLightsOut) {
  const fs::path out = dir / "atrium-bare.glb";
  const RunResult ex = run({"scene", "export", "depth-step", out.string(), "--no-camera", "--no-lights"});
  ASSERT_EQ(ex.exitCode, 0) << ex.err;
  const RunResult info = run({"scene", "info", out.string(), "--json"});
  ASSERT_EQ(info.exitCode, 0) << info.err;
  const json j = json::parse(info.out);
  EXPECT_EQ(j["cameras"], 0);
  EXPECT_EQ(j["lights"]["total"], 0);
  EXPECT_EQ(j["triangles"], 4);
}

TEST_F(AutoScene, AGltfWithItsOwnCameraAndLightsIsUnchanged) {
  RunResult r;
  const json j = renderJson({"--scene", own.string()}, dir / "own-out", r);
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  EXPECT_EQ(r.err.find("automatic"), std::string::npos) << r.err;
  EXPECT_EQ(j["camera"]["source"], "scene");
  EXPECT_EQ(j["lights"]["source"], "scene");
  EXPECT_EQ(j["lights"]["count"], 1);
  // An atrium config's own light count (scene_params) does not carry over to another --scene.
  writeFile(dir / "atrium.json", R"({"name": "a", "scene": "atrium", "scene_params": {"lights": 20}})");
  const json withConfig = renderJson({(dir / "atrium.json").string(), "--scene", own.string()}, dir / "cfg-out", r);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(withConfig["lights"]["source"], "scene");
  EXPECT_EQ(withConfig["lights"]["count"], 1);
  // ... and draws the same image as the built-in it was exported from.
  const json b = renderJson({"--scene", "cube"}, dir / "builtin-out", r);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(readFile(dir / "own-out" / "color.png") == readFile(dir / "builtin-out" / "color.png"), true);
}

// A glTF whose own camera is orthographic renders (through the hardware path's reverse-Z
// orthographic matrix) with light culling off, and says so; asking for culling is a clear error.
TEST_F(AutoScene, AGltfWithAnOrthographicCameraRenders) {
  json doc = json::parse(readFile(own));
  ASSERT_TRUE(doc.contains("cameras"));
  for (json& c : doc["cameras"]) {
    c.erase("perspective");
    c["type"] = "orthographic";
    c["orthographic"] = {{"xmag", 4.0}, {"ymag", 2.25}, {"znear", 0.1}, {"zfar", 100.0}};
  }
  const fs::path ortho = dir / "ortho.gltf";
  writeFile(ortho, doc.dump(1));
  RunResult r;
  const json j = renderJson({"--scene", ortho.string()}, dir / "ortho-out", r);
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  EXPECT_NE(r.err.find("its camera is orthographic: light_culling=false"), std::string::npos) << r.err;
  EXPECT_EQ(j["camera"]["source"], "scene");
  EXPECT_EQ(j["params"]["light_culling"], false);
  // Shadows are traced; the CPU references of the analysis reconstruct perspective views only,
  // and the results say so rather than count.
  const json& passes = j["passes_run"];
  EXPECT_NE(std::find(passes.begin(), passes.end(), "shadows"), passes.end()) << passes.dump();
  EXPECT_NE(j.value("analysis_not_run", "").find("orthographic"), std::string::npos) << j.dump();
  const RunResult culled =
      run({"render", "--scene", ortho.string(), "--set", "light_culling=true", "--out", (dir / "c").string()});
  EXPECT_EQ(culled.exitCode, 2);
  EXPECT_NE(culled.err.find("needs light_culling=false"), std::string::npos) << culled.err;
}

TEST_F(AutoScene, LightCountAndCameraAutoWorkOnAnyScene) {
  RunResult r;
  const json j =
      renderJson({"--scene", own.string(), "--set", "light_count=3", "--set", "camera=auto"}, dir / "asked-out", r);
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  EXPECT_EQ(j["camera"]["source"], "auto");
  EXPECT_EQ(j["camera"]["name"], "auto");
  EXPECT_EQ(j["lights"]["source"], "auto");
  EXPECT_EQ(j["lights"]["count"], 3);
  const json hc = renderJson({"--scene", "depth-step", "--set", "light_count=40", "--set", "light_lists=bitmask"},
                             dir / "hard-out", r);
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  EXPECT_EQ(hc["lights"]["count"], 40);
  EXPECT_EQ(hc["rays"].value("dropped_by_overflow", uint64_t(1)), 0u);

  const RunResult bad =
      run({"render", "--scene", own.string(), "--set", "camera=front", "--out", (dir / "x").string()});
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_NE(bad.err.find("camera=auto"), std::string::npos) << bad.err;
  const RunResult scale =
      run({"render", "--scene", own.string(), "--set", "triangle_scale=2", "--out", (dir / "y").string()});
  EXPECT_EQ(scale.exitCode, 2);
  EXPECT_NE(scale.err.find("triangle_scale applies only to the built-in atrium"), std::string::npos) << scale.err;
}

TEST_F(AutoScene, ASweepOverLightCountsOfABareGltfRecordsTheSources) {
  const json config = {{"name", "bare-lights"},
                       {"scene", bare.string()},
                       {"camera", "auto"},
                       {"resolution", {64, 36}},
                       {"frames", {{"warmup", 1}, {"measured", 2}}},
                       {"defaults", {{"light_lists", "bitmask"}}},
                       {"variants",
                        {{{"name", "2 lights"}, {"params", {{"light_count", 2}}}},
                         {{"name", "40 lights"}, {"params", {{"light_count", 40}}}}}}};
  writeFile(dir / "bare.json", config.dump(1));
  const RunResult r = run({"sweep", (dir / "bare.json").string(), "--out", (dir / "sweep").string(), "--no-images"});
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  const json results = json::parse(readFile(dir / "sweep" / "results.json"));
  EXPECT_EQ(results["context"]["scene"]["camera_source"], "auto");
  EXPECT_EQ(results["context"]["scene"]["lights_source"], "auto");
  ASSERT_EQ(results["runs"].size(), 2u);
  const uint64_t counts[] = {2, 40};
  for (size_t i = 0; i < 2; ++i) {
    const json& run = results["runs"][i];
    ASSERT_EQ(run.value("status", ""), "ok") << run.dump();
    EXPECT_EQ(run["scene"]["lights"], counts[i]);
    EXPECT_EQ(run["scene"]["lights_source"], "auto");
    EXPECT_EQ(run["scene"]["camera_source"], "auto");
    EXPECT_GT(run["rays"].value("traced", uint64_t(0)), 0u);
  }
}

}  // namespace
