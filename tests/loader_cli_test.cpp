// What a user expects of the glTF loader and the command line (docs/usage.md "Loader
// strictness"), end to end through the built hybridbench on real glTF files: the assimp test
// models (tests/fixtures/assimp/README.md) and small edits of them. Every refusal is exit 2 and
// ONE stderr line naming what is wrong and how to go on, and leaves the test's folder as it was;
// what is skipped or ignored is said in one warning line per kind and the rest renders.
#include <algorithm>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tool_process.h"

namespace loader_cli {

using namespace hb::testing;

const fs::path kAssimp = fs::path(HYBRIDBENCH_SOURCE_DIR) / "tests/fixtures/assimp";
const fs::path kCube = kAssimp / "glTF2/IncorrectVertexArrays/Cube.gltf";

size_t linesOf(const std::string& text) { return static_cast<size_t>(std::count(text.begin(), text.end(), '\n')); }

class LoaderCli : public ToolTest {
 protected:
  // The assimp cube file with `edit` applied, written into the test folder beside a copy of its
  // Cube.bin.
  fs::path editedCube(const std::function<void(json&)>& edit) {
    json doc = readJson(kCube);
    edit(doc);
    fs::copy_file(kCube.parent_path() / "Cube.bin", dir / "Cube.bin", fs::copy_options::overwrite_existing);
    writeFile(dir / "edited.gltf", doc.dump(1));
    return dir / "edited.gltf";
  }

  std::vector<std::string> render(const std::string& scene, std::vector<std::string> extra = {}) {
    std::vector<std::string> a{"render", "--scene", scene, "--size", "64x36", "--out", (dir / "out").string()};
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  }
};

// ---- glTF 1.0 is named as such, with how to convert it ----------------------------------------

TEST_F(LoaderCli, AGltf1FileIsRefusedAsGltf1WithHowToConvertIt) {
  const std::string twoBoxes = (kAssimp / "glTF/TwoBoxes.gltf").string();
  expectRefused({"scene", "info", twoBoxes}, {twoBoxes, "glTF 1.0", "asset.version \"1.0\"", "gltf-pipeline -i"},
                {"defaultScene", "expected"});
  expectRefused(render(twoBoxes), {"glTF 1.0", "gltf-pipeline"});

  // Binary glTF 1.0 (KHR_binary_glTF): "glTF", version 1, length, then the JSON's length and format 0.
  std::string text = readFile(kAssimp / "glTF/TwoBoxes.gltf");
  while (text.size() % 4) text += ' ';
  auto u32 = [](uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  writeFile(dir / "TwoBoxes.glb", "glTF" + u32(1) + u32(static_cast<uint32_t>(20 + text.size())) +
                                      u32(static_cast<uint32_t>(text.size())) + u32(0) + text);
  expectRefused({"scene", "info", (dir / "TwoBoxes.glb").string()},
                {"TwoBoxes.glb", "binary glTF 1.0", "gltf-pipeline -i TwoBoxes.glb -o TwoBoxes-2.0.glb"});
}

// ---- one broken mesh does not refuse the file ---------------------------------------------------

TEST_F(LoaderCli, TruncatedMeshesAreSkippedWithOneWarningAndTheCubesRender) {
  // Cube and IndexedCube are whole (12 triangles each); TruncatedCube (35 vertices) and
  // TruncatedIndexedCube (35 indices) make no whole triangles; four meshes are lines.
  const RunResult info = run({"scene", "info", kCube.string(), "--json"});
  ASSERT_EQ(info.exitCode, 0) << info.err;
  const json summary = json::parse(info.out, nullptr, false);
  EXPECT_EQ(summary["triangles"], 24) << info.out;
  EXPECT_NE(info.err.find("skipped 2 triangle primitive(s) whose data is broken"), std::string::npos) << info.err;
  EXPECT_NE(info.err.find("in mesh \"TruncatedCube\": meshes[1].primitives[0].attributes.POSITION: 35 vertices"),
            std::string::npos)
      << info.err;
  EXPECT_NE(info.err.find("skipped 4 primitive(s) of points or lines"), std::string::npos) << info.err;
  EXPECT_EQ(linesOf(info.err), 2u) << "one line per kind of skip: " << info.err;

  const RunResult r = run(render(kCube.string()));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.err.find("whose data is broken"), std::string::npos) << r.err;
  EXPECT_EQ(readJson(dir / "out" / "render.json")["context"]["scene"]["triangles"], 24);
}

TEST_F(LoaderCli, AFileOfNothingButBrokenMeshesIsRefusedWithTheFirstOnesFault) {
  const fs::path onlyBroken = editedCube([](json& d) { d["scenes"][0]["nodes"] = {1, 5}; });
  expectRefused({"scene", "info", onlyBroken.string()}, {"edited.gltf", "meshes[1].primitives[0].attributes.POSITION",
                                                         "35 vertices do not make whole triangles", "multiple of 3"});
}

// ---- a missing .bin is named, with the fix of supplying it -------------------------------------

TEST_F(LoaderCli, AMissingBinNamesTheFileToSupply) {
  fs::copy_file(kCube, dir / "Cube.gltf");
  expectRefused(
      {"scene", "info", (dir / "Cube.gltf").string()},
      {"Cube.gltf", "buffers[0].uri", "\"Cube.bin\" is not there", (dir / "Cube.bin").string(), "put Cube.bin"},
      {"re-export", "glTF 2.0"});
}

// ---- strict where the image depends on it, lenient where it does not ---------------------------

TEST_F(LoaderCli, AnIllTypedTextureTransformIsRefusedAndANumberForANameIsNot) {
  const fs::path transform = editedCube([](json& d) {
    d["materials"] = {
        {{"pbrMetallicRoughness",
          {{"baseColorTexture", {{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"rotation", "90"}}}}}}}}}}};
    d["meshes"][0]["primitives"][0]["material"] = 0;
  });
  expectRefused({"scene", "info", transform.string()},
                {"materials[0].pbrMetallicRoughness.baseColorTexture.extensions.KHR_texture_transform.rotation",
                 "expected a number, got the string \"90\""});

  const fs::path light = editedCube([](json& d) {
    d["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", "100"}}};
  });
  expectRefused({"scene", "info", light.string()},
                {"extensions.KHR_lights_punctual.lights[0].intensity", "expected a number"});

  const fs::path named = editedCube([](json& d) {
    d["scenes"][0]["name"] = 7;
    d["nodes"][0]["name"] = 1;
  });
  const RunResult r = run({"scene", "info", named.string(), "--json"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(json::parse(r.out, nullptr, false)["name"], "edited") << "the file's stem names the scene";
  EXPECT_NE(
      r.err.find("ignored 2 name(s) that are not strings (a name changes nothing drawn), first scenes[0].name (7)"),
      std::string::npos)
      << r.err;
}

// ---- what is not read is said once ---------------------------------------------------------------

TEST_F(LoaderCli, SkinsMorphTargetsAndAnimationsAreNamedInOneWarning) {
  const fs::path animated = editedCube([](json& d) {
    d["skins"] = {{{"joints", {0}}}};
    d["meshes"][0]["primitives"][0]["targets"] = {{{"POSITION", 1}}};
    d["meshes"][4]["primitives"][0]["targets"] = {{{"POSITION", 1}}};
  });
  const RunResult r = run({"scene", "info", animated.string()});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.err.find("ignored 1 skin(s) and the morph targets of 2 primitive(s) (not read)"), std::string::npos)
      << r.err;
  const RunResult plain = run({"scene", "info", kCube.string()});
  EXPECT_EQ(plain.err.find("skin"), std::string::npos) << plain.err;
}

// ---- typos get a did-you-mean --------------------------------------------------------------------

TEST_F(LoaderCli, TyposOfCommandsFlagsAndSceneNamesGetADidYouMean) {
  expectRefused({"rendr", "--scene", "plane"}, {"unknown command \"rendr\"", "did you mean \"render\"?"});
  expectRefused({"scene", "exprot", "cube", (dir / "c.gltf").string()},
                {"scene: unknown command \"exprot\"", "did you mean \"export\"?", "hybridbench scene --help"});
  expectRefused({"render", "--sizes", "64x36", "--out", (dir / "o").string()},
                {"render: unknown flag \"--sizes\"", "did you mean \"--size\"?", "hybridbench render --help"});
  expectRefused({"sweep", "--dryrun"}, {"did you mean \"--dry-run\"?"});
  expectRefused(render("atrum"), {"\"atrum\"", "did you mean \"atrium\"?"});
  expectRefused({"scene", "info", "atrum"}, {"did you mean \"atrium\"?"});
  // Far from every name: the list, not a guess.
  expectRefused({"scene", "info", "sponza"}, {"atrium, plane"}, {"did you mean"});
}

// ---- the environment from the command line --------------------------------------------------------

TEST_F(LoaderCli, SetEnvironmentGivesTheSceneASky) {
  const std::string sky = (fs::path(HYBRIDBENCH_SOURCE_DIR) / "scenes/environments/sky.hdr").string();
  const std::vector<std::string> light{"--set", R"(environment_light={"directions": 4, "ldm_resolution": 8})"};
  std::vector<std::string> args = render("plane", light);
  args.insert(args.end(), {"--set", "environment=" + sky});
  const RunResult r = run(args);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const json renderJson = readJson(dir / "out" / "render.json");
  const std::string passes = renderJson["passes_run"].dump();
  EXPECT_NE(passes.find("environment_light"), std::string::npos) << renderJson.dump(1).substr(0, 4000);

  fs::remove_all(dir / "out");
  expectRefused(render("plane", {"--set", "environment=" + (dir / "missing.hdr").string()}),
                {"--set environment=", "missing.hdr"});
  expectRefused(render("plane", {"--set", "environment=true"}), {"--set environment=true", "an .hdr image path"});
  expectRefused(render("plane", {"--set", "enviroment=sky.hdr"}), {"did you mean \"environment\"?"});

  // sweep takes it as well, into its config.
  const std::string config = hb::testing::kSweepFixture.string();
  const RunResult dry = run({"sweep", config, "--dry-run", "--set", "environment=" + sky});
  EXPECT_EQ(dry.exitCode, 0) << dry.err;
  expectRefused({"sweep", config, "--dry-run", "--set", "environment=" + (dir / "missing.hdr").string()},
                {"--set environment=", "missing.hdr"});
}

}  // namespace loader_cli
