// What a new user hit (docs/usage.md): end-to-end tests through the built hybridbench, one per
// thing that lost data or gave a wrong answer. Every refusal is exit 2, ONE stderr line naming
// what is wrong and how to go on, and leaves the test's folder exactly as it was (every file's
// bytes compared before and after, no file or folder created). Runs are tiny: the one-light
// "plane" scene at 64x36 on lavapipe.
#include <algorithm>
#include <filesystem>
#include <map>
#include <regex>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tool_process.h"

namespace {

using namespace hb::testing;

class NewUser : public ToolTest {
 protected:
  // A two-variant sweep of the plane at 64x36: seconds on lavapipe.
  fs::path tinyConfig() {
    const fs::path p = dir / "tiny.json";
    writeFile(p, json{{"name", "tiny"},
                      {"scene", "plane"},
                      {"resolution", {64, 36}},
                      {"frames", {{"warmup", 0}, {"measured", 3}}},
                      {"grid", {{"tile_size", {8, 16}}}}}
                     .dump());
    return p;
  }

  RunResult sweep(const fs::path& out, std::vector<std::string> extra = {}) {
    std::vector<std::string> a{"sweep", tinyConfig().string(), "--no-images", "--out", out.string()};
    a.insert(a.end(), extra.begin(), extra.end());
    return run(a);
  }

  std::vector<std::string> render(const fs::path& out, std::vector<std::string> extra = {},
                                  const std::string& scene = "plane") {
    std::vector<std::string> a{"render", "--scene", scene, "--size", "64x36", "--out", out.string()};
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  }
};

// ---- 1. earlier results are never lost without a word ----------------------------------------

TEST_F(NewUser, SweepIntoAFolderWithResultsIsRefusedAndForceMovesThemAside) {
  const fs::path out = dir / "s5";
  ASSERT_EQ(sweep(out).exitCode, 0);
  const std::string first = readFile(out / "results.json");
  expectRefused(
      {"sweep", tinyConfig().string(), "--no-images", "--out", out.string(), "--frames", "2"},
      {out.string(), "already holds results", "results.json with 2 run(s)", "--resume", "--force", "fresh folder"});
  expectRefused({"sweep", tinyConfig().string(), "--out", out.string(), "--resume", "--force"},
                {"--resume", "--force"});
  const RunResult forced = sweep(out, {"--frames", "2", "--force"});
  ASSERT_EQ(forced.exitCode, 0) << forced.err;
  std::vector<fs::path> aside;
  for (const auto& e : fs::directory_iterator(out))
    if (e.path().filename().string().rfind("previous-", 0) == 0) aside.push_back(e.path());
  ASSERT_EQ(aside.size(), 1u);
  EXPECT_EQ(readFile(aside[0] / "results.json"), first) << "the earlier results must be kept, byte for byte";
  EXPECT_NE(forced.out.find(aside[0].string()), std::string::npos) << forced.out;
  EXPECT_EQ(readJson(out / "results.json")["context"]["frames"]["measured"], 2);
}

TEST_F(NewUser, RenderIntoAFolderWithARenderIsRefusedAndForceMovesItAside) {
  const fs::path out = dir / "r";
  ASSERT_EQ(run(render(out)).exitCode, 0);
  const std::string first = readFile(out / "render.json");
  expectRefused(render(out), {out.string(), "already holds results", "render.json", "--force"});
  const RunResult forced = run(render(out, {"--force"}));
  ASSERT_EQ(forced.exitCode, 0) << forced.err;
  size_t aside = 0;
  for (const auto& e : fs::directory_iterator(out))
    if (e.path().filename().string().rfind("previous-", 0) == 0) {
      ++aside;
      EXPECT_EQ(readFile(e.path() / "render.json"), first);
    }
  EXPECT_EQ(aside, 1u);
}

// ---- 2. timing caveats travel with the numbers ------------------------------------------------

TEST_F(NewUser, CompareOnACpuDeviceMarksPassesNotTimedAndPrintsTheCaveat) {
  ASSERT_EQ(sweep(dir / "a").exitCode, 0);
  // B: every pass 3x slower, the frames unchanged. On a CPU device the passes are "not timed":
  // no verdict and no exit 1; the frame rows compare as before (identical samples: p = 1).
  json b = readJson(dir / "a" / "results.json");
  for (json& run : b["runs"])
    for (auto& [pass, stats] : run["passes"].items()) {
      for (json& x : stats["samples"]) x = x.get<double>() * 3;
      stats["median"] = stats["median"].get<double>() * 3;
    }
  writeFile(dir / "b.json", b.dump());
  const RunResult r = run({"compare", (dir / "a" / "results.json").string(), (dir / "b.json").string(), "--json"});
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
  const json report = json::parse(r.out, nullptr, false);
  ASSERT_TRUE(report.is_object()) << r.out;
  size_t notTimed = 0;
  for (const json& row : report["rows"]) {
    if (row["pass"] == "frame")
      EXPECT_NE(row["verdict"], "not timed");
    else
      EXPECT_EQ(row["verdict"], "not timed") << row.dump();
    notTimed += row["verdict"] == "not timed";
  }
  EXPECT_GE(notTimed, 2u);
  ASSERT_FALSE(report["caveats"].empty());
  const RunResult md = run({"compare", (dir / "a" / "results.json").string(), (dir / "b.json").string()});
  EXPECT_NE(md.out.find("caveat: A: CPU implementation"), std::string::npos) << md.out;
  EXPECT_NE(md.out.find("| not timed |"), std::string::npos) << md.out;
}

TEST_F(NewUser, FramesGivenOnTheCommandLineAreWhatTheNoteSaysAndWhatRan) {
  const RunResult r = sweep(dir / "s", {"--frames", "7"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("measured frames 7 (--frames)"), std::string::npos) << r.out;
  const json results = readJson(dir / "s" / "results.json");
  EXPECT_EQ(results["context"]["frames"]["measured"], 7);
  for (const json& run : results["runs"]) EXPECT_EQ(run["frame_ms"]["samples"].size(), 7u);
}

TEST_F(NewUser, RenderPrintsTheCaveatAndWhatTheFrameSpendsOutsideItsPasses) {
  const RunResult r = run(render(dir / "r"));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("frame - passes"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("caveat: CPU implementation"), std::string::npos) << r.out;
}

TEST_F(NewUser, TablesAndTheAccuracyReportPrintTheCaveat) {
  ASSERT_EQ(sweep(dir / "s").exitCode, 0);
  const RunResult md = run({"tables", (dir / "s" / "results.json").string()});
  ASSERT_EQ(md.exitCode, 0) << md.err;
  // Once in the thesis tables, once in the accuracy report.
  const std::regex caveat("Caveat: CPU implementation");
  EXPECT_EQ(std::distance(std::sregex_iterator(md.out.begin(), md.out.end(), caveat), std::sregex_iterator()), 2)
      << md.out;
  const RunResult csv = run({"tables", (dir / "s" / "results.json").string(), "--format", "csv"});
  EXPECT_NE(csv.err.find("caveat: CPU implementation"), std::string::npos) << csv.err;
}

// ---- 3. a folder where a file belongs ----------------------------------------------------------

TEST_F(NewUser, AFolderWhereAFileBelongsIsOneLineForEveryCommand) {
  fs::create_directories(dir / "folder");
  const std::string folder = (dir / "folder").string();
  ASSERT_EQ(sweep(dir / "s").exitCode, 0);
  const std::string results = (dir / "s" / "results.json").string();
  expectRefused({"tables", folder}, {folder, "is a folder, not a file", "results.json"});
  expectRefused({"compare", folder, results}, {folder, "is a folder"});
  expectRefused({"compare", results, folder}, {folder, "is a folder"});
  expectRefused({"sweep", folder, "--out", (dir / "o").string()}, {folder, "is a folder", "config"});
  expectRefused({"render", folder, "--out", (dir / "o").string()}, {folder, "is a folder"});
  expectRefused({"render", "--scene", folder + "/x.gltf", "--out", (dir / "o").string()}, {"x.gltf", "no such file"});
  fs::create_directories(dir / "scene.gltf");
  expectRefused({"render", "--scene", (dir / "scene.gltf").string(), "--out", (dir / "o").string()},
                {"scene.gltf", "is a folder"});
  expectRefused({"scene", "info", (dir / "scene.gltf").string()}, {"scene.gltf", "is a folder"});
  expectRefused({"scene", "export", "plane", folder}, {folder, "is a folder, not a file"});
  writeFile(dir / "file", "x");
  expectRefused(render(dir / "file"), {"file", "is a file, not a folder"});
}

// ---- 4. empty or malformed scenes are refused before anything is printed or created -----------

// A one-triangle glTF (positions only, no indices), with `edit` applied to its JSON.
fs::path gltfWith(const fs::path& dir, const std::string& name, const std::function<void(json&)>& edit) {
  json doc = {{"asset", {{"version", "2.0"}}},
              {"scene", 0},
              {"scenes", {{{"nodes", {0}}}}},
              {"nodes", {{{"mesh", 0}}}},
              {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}}}}}}},
              {"buffers",
               {{{"byteLength", 36},
                 {"uri", "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}}}},
              {"bufferViews", {{{"buffer", 0}, {"byteLength", 36}}}},
              {"accessors", {trianglePositionsAccessor()}}};
  edit(doc);
  const fs::path p = dir / name;
  writeFile(p, doc.dump(1));
  return p;
}

TEST_F(NewUser, EmptyAndMalformedScenesAreRefusedNamingTheFileAndTheGltfPath) {
  const fs::path scenes = dir / "scenes";
  fs::create_directories(scenes);
  const fs::path ok = gltfWith(scenes, "ok.gltf", [](json&) {});
  const fs::path noScene = gltfWith(scenes, "no-scene.gltf", [](json& d) {
    d.erase("scene");
    d.erase("scenes");
    d.erase("nodes");
  });
  const fs::path noNodes = gltfWith(scenes, "no-nodes.gltf", [](json& d) { d["scenes"][0]["nodes"] = json::array(); });
  const fs::path noMesh = gltfWith(scenes, "no-mesh.gltf", [](json& d) { d["nodes"][0].erase("mesh"); });
  const fs::path object = gltfWith(scenes, "primitives-object.gltf",
                                   [](json& d) { d["meshes"][0]["primitives"] = d["meshes"][0]["primitives"][0]; });
  const fs::path out = dir / "out";
  expectRefused(render(out, {}, noScene.string()), {noScene.string(), "scenes:", "no scene and no nodes"});
  expectRefused(render(out, {}, noNodes.string()), {noNodes.string(), "scenes[0].nodes:", "no nodes"});
  expectRefused(render(out, {}, noMesh.string()), {noMesh.string(), "scenes[0]:", "has a mesh"});
  expectRefused(render(out, {}, object.string()),
                {object.string(), "meshes[0].primitives: expected an array, got an object"});
  expectRefused({"sweep", tinyConfig().string(), "--scene", object.string(), "--out", (dir / "o").string()},
                {object.string(), "meshes[0].primitives: expected an array"});
  // The well-formed one renders (the checks refuse only what is wrong).
  const RunResult good = run(render(out, {}, ok.string()));
  EXPECT_EQ(good.exitCode, 0) << good.err;

  const RunResult list = run({"scene", "list", "--dir", scenes.string(), "--json"});
  ASSERT_EQ(list.exitCode, 0) << list.err;
  const json listing = json::parse(list.out, nullptr, false);
  ASSERT_TRUE(listing.is_object()) << list.out;
  size_t errors = 0, loads = 0;
  for (const json& f : listing["files"]) {
    if (f.contains("error"))
      ++errors;
    else
      ++loads;
  }
  EXPECT_EQ(errors, 4u) << list.out;
  EXPECT_EQ(loads, 1u) << list.out;
}

// ---- 5. --set keys ------------------------------------------------------------------------------

TEST_F(NewUser, SetSaysDidYouMeanAndListsEveryKeyItTakes) {
  expectRefused(render(dir / "o", {"--set", "shadow=false"}), {"unknown key \"shadow\"", "did you mean \"shadows\""});
  const RunResult r = expectRefused(render(dir / "o", {"--set", "zzzzzzzz=1"}), {"unknown key"});
  for (const char* key : {"tile_size", "shadows", "ambient_occlusion", "indirect", "camera"})
    EXPECT_NE(r.err.find(key), std::string::npos) << key << ": " << r.err;
  expectRefused({"sweep", tinyConfig().string(), "--set", "tile_sise=8", "--out", (dir / "o").string()},
                {"--set tile_sise=8", "did you mean \"tile_size\""});
}

// ---- 6. render.json says what made it -----------------------------------------------------------

TEST_F(NewUser, RenderJsonCarriesItsContext) {
  ASSERT_EQ(run(render(dir / "r")).exitCode, 0);
  const json r = readJson(dir / "r" / "render.json");
  const json& c = r["context"];
  for (const char* k : {"name", "driver", "type", "uuid"}) EXPECT_TRUE(c["device"].contains(k)) << k;
  EXPECT_EQ(c["tool"]["name"], "hybridbench");
  EXPECT_TRUE(c["tool"].contains("version") && c["tool"].contains("git"));
  EXPECT_EQ(c["scene"]["name"], "plane");
  EXPECT_EQ(c["scene"]["sha256"].get<std::string>().size(), 64u);
  EXPECT_EQ(c["resolution"], json::array({64, 36}));
  EXPECT_TRUE(c.contains("timing_caveat"));  // lavapipe, a CPU device
  // The clocks around the timed frame (gpu/telemetry.h): on a device without NVML, one field says why.
  ASSERT_TRUE(c["device"]["telemetry"].is_object());
  ASSERT_TRUE(r["telemetry"].is_object());
  EXPECT_EQ(r["telemetry"]["available"], c["device"]["telemetry"]["available"]);
  if (r["telemetry"]["available"] == false)
    EXPECT_NE(r["telemetry"].value("reason", ""), "") << r["telemetry"].dump();
  else
    EXPECT_TRUE(r["telemetry"].contains("before") && r["telemetry"].contains("after")) << r["telemetry"].dump();
  ASSERT_TRUE(r["frame_minus_passes_ms"].is_number());
  // The frame minus its passes, the sub-passes ("raster3d.tiles") inside theirs.
  double passes = 0;
  for (const auto& [pass, ms] : r["timing_ms"].items())
    if (pass != "frame" && pass.find('.') == std::string::npos) passes += ms.get<double>();
  EXPECT_DOUBLE_EQ(r["frame_minus_passes_ms"].get<double>(), r["timing_ms"]["frame"].get<double>() - passes);
}

// ---- 7. tables with two files of the same variants ----------------------------------------------

TEST_F(NewUser, TablesRefusesTheSameVariantsTwiceUnlessAllowedThenNamesEachRowsFile) {
  ASSERT_EQ(sweep(dir / "a").exitCode, 0);
  fs::copy_file(dir / "a" / "results.json", dir / "b.json");
  const std::string a = (dir / "a" / "results.json").string(), b = (dir / "b.json").string();
  expectRefused({"tables", a, b}, {b, "tile_size=8", "also in", a, "--allow-duplicates"});
  const RunResult r = run({"tables", a, b, "--allow-duplicates"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("tile_size=8 [" + a + "]"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("tile_size=8 [" + b + "]"), std::string::npos) << r.out;
}

// ---- 8. small things ------------------------------------------------------------------------------

TEST_F(NewUser, SmallThings) {
  // "1 light", not "1 lights".
  const RunResult r = run(render(dir / "r"));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find(" 2 triangles, 1 light, 64x36"), std::string::npos) << r.out;
  // No estimate before the first variant finished: "eta --", not "eta 0s".
  const RunResult s = sweep(dir / "s");
  ASSERT_EQ(s.exitCode, 0) << s.err;
  EXPECT_NE(s.out.find("[0/2] tile_size=8 (elapsed 0s, eta --)"), std::string::npos) << s.out;
  // Ray throughput is measured at least 3 times, as the docs say, on a CPU device too.
  for (const json& run : readJson(dir / "s" / "results.json")["runs"])
    EXPECT_GE(run["raybench"]["repetitions"].get<int>(), 3) << run.dump();
  // tables on a render.json names the file and what it is.
  expectRefused({"tables", (dir / "r" / "render.json").string()},
                {(dir / "r" / "render.json").string(), "is a render.json", "results.json"});
}

// ---- 9. sweeping without writing a config -------------------------------------------------------

TEST_F(NewUser, SweepTakesSetSceneAndSizeAndDryRunWritesNothing) {
  const fs::path out = dir / "s";
  const std::vector<std::string> args{
      "sweep", tinyConfig().string(), "--scene",     "cube",  "--size",    "48x32", "--set", "normal_culling=naive",
      "--set", "shadows=true",        "--no-images", "--out", out.string()};
  std::vector<std::string> dry = args;
  dry.push_back("--dry-run");
  const auto before = snapshot(dir);
  const RunResult d = run(dry);
  ASSERT_EQ(d.exitCode, 0) << d.err;
  EXPECT_TRUE(snapshot(dir) == before) << "a dry run wrote something";
  EXPECT_NE(d.out.find("2 variants"), std::string::npos) << d.out;
  EXPECT_NE(d.out.find("\"normal_culling\":\"naive\""), std::string::npos) << d.out;
  EXPECT_NE(d.out.find("\"resolution\":[48,32]"), std::string::npos) << d.out;
  EXPECT_NE(d.out.find("1. tile_size=8: (the defaults)"), std::string::npos) << d.out;
  EXPECT_NE(d.out.find("2. tile_size=16: {\"tile_size\":16}"), std::string::npos) << d.out;
  EXPECT_NE(d.out.find("estimate: ~"), std::string::npos) << d.out;

  const RunResult r = run(args);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const json results = readJson(out / "results.json");
  EXPECT_EQ(results["context"]["scene"]["name"], "cube");
  // The overrides as given, for history to keep these runs apart from the config's own.
  EXPECT_EQ(results["context"]["overrides"]["set"], json::array({"normal_culling=naive", "shadows=true"}));
  ASSERT_EQ(results["runs"].size(), 2u);
  for (const json& run : results["runs"]) {
    EXPECT_EQ(run["params"]["resolution"], json::array({48, 32}));
    EXPECT_EQ(run["params"]["normal_culling"], "naive");
  }
  // A parameter the config sweeps cannot be set for every variant.
  expectRefused({"sweep", tinyConfig().string(), "--set", "tile_size=32", "--out", (dir / "o").string()},
                {"--set tile_size=32", "sweeps tile_size", "grid"});
}

}  // namespace
