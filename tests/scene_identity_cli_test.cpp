// A scene is its content, not its path (docs/results-format.md#identity): the same config and glTF
// in two folders (two checkouts, two runners) sweep to results that `compare`, `merge` and
// `sweep --resume` accept, with one warning that names both paths; the scene with one vertex moved
// is refused, naming both sha256s. And what traced is named from runs' backend_choice, not from what the device offers.
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tool_process.h"

// A named namespace: the unity build puts this file beside others with helpers of the same names.
namespace scene_identity_cli_test {

using namespace hb::testing;

const fs::path kSource = HYBRIDBENCH_SOURCE_DIR;

// Two variants, one per part of `--shard K/2` (equal costs: variant k goes to part k), at the
// smallest size, on a 28-vertex scene with its own camera and light.
constexpr const char* kConfig = R"({
  "name": "scene-identity",
  "description": "tests/scene_identity_cli_test.cpp: the same scene in two folders",
  "scene": "cube.gltf",
  "resolution": [64, 36],
  "frames": {"warmup": 0, "measured": 2},
  "variants": [
    {"name": "compute", "params": {"backend": "compute"}},
    {"name": "rayquery", "params": {"backend": "rayquery"}}
  ]
})";

size_t countContaining(const json& lines, const std::string& needle) {
  return size_t(std::count_if(lines.begin(), lines.end(),
                              [&](const json& l) { return l.get<std::string>().find(needle) != std::string::npos; }));
}

class SceneIdentity : public ToolTest {
 protected:
  // A checkout: the config and a copy of scenes/cube.gltf in dir/name.
  fs::path checkout(const std::string& name) {
    const fs::path folder = dir / name;
    fs::create_directories(folder);
    fs::copy_file(kSource / "scenes/cube.gltf", folder / "cube.gltf");
    hb::testing::writeFile(folder / "config.json", kConfig);
    return folder;
  }
  // Sweeps part `part` of 2 of the checkout's config into dir/out; returns the results folder.
  fs::path sweep(const fs::path& folder, int part, const std::string& out) {
    const RunResult r = run({"sweep", (folder / "config.json").string(), "--shard", std::to_string(part) + "/2",
                             "--no-images", "--out", (dir / out).string()});
    EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
    return dir / out;
  }
};

TEST_F(SceneIdentity, TheSameSceneAtAnotherPathComparesAndMergesWithOneWarningAndAMovedVertexIsRefused) {
  const fs::path one = checkout("one"), two = checkout("two");
  const fs::path a0 = sweep(one, 0, "a0"), b0 = sweep(two, 0, "b0"), b1 = sweep(two, 1, "b1");
  const std::string sceneOne = (one / "cube.gltf").string(), sceneTwo = (two / "cube.gltf").string();
  const json contextA = hb::testing::readJson(a0 / "results.json")["context"];
  EXPECT_EQ(contextA["config"]["scene"], sceneOne);
  EXPECT_EQ(contextA["config_file"], (one / "config.json").string());

  // compare: the same variant of the same scene from two folders.
  const RunResult c =
      run({"compare", (a0 / "results.json").string(), (b0 / "results.json").string(), "--format", "json"});
  EXPECT_EQ(c.exitCode, 0) << c.err;
  const json report = json::parse(c.out, nullptr, false);
  ASSERT_TRUE(report.is_object()) << c.out << c.err;
  EXPECT_EQ(countContaining(report["warnings"], "other paths"), 1u) << report["warnings"].dump(1);
  EXPECT_EQ(countContaining(report["warnings"], "scene (A: \"" + sceneOne + "\", B: \"" + sceneTwo + "\")"), 1u)
      << report["warnings"].dump(1);
  EXPECT_EQ(report["a"]["ray_tracing"], "compute");

  // merge: the two parts of the sweep, one from each folder; each part records its paths.
  const RunResult m = run({"merge", a0.string(), b1.string(), "--out", (dir / "merged").string()});
  EXPECT_EQ(m.exitCode, 0) << m.err;
  size_t pathWarnings = 0;
  for (size_t at = m.err.find("other paths"); at != std::string::npos; at = m.err.find("other paths", at + 1))
    ++pathWarnings;
  EXPECT_EQ(pathWarnings, 1u) << m.err;
  EXPECT_NE(m.err.find("scene (" + a0.string() + ": \"" + sceneOne + "\", " + b1.string() + ": \"" + sceneTwo + "\")"),
            std::string::npos)
      << m.err;
  const json merged = hb::testing::readJson(dir / "merged/results.json");
  ASSERT_EQ(merged["context"]["merged_from"].size(), 2u);
  EXPECT_EQ(merged["context"]["merged_from"][1]["paths"]["scene"], sceneTwo);
  // The merged runs traced differently: each ray tracer with its runs.
  const RunResult t = run({"tables", (dir / "merged/results.json").string()});
  EXPECT_NE(t.out.find("ray tracing compute (1 run: compute), rayquery (1 run: rayquery) ·"), std::string::npos)
      << t.out.substr(0, 600);

  // sweep --resume from the other folder: every run kept, one warning.
  const std::vector<std::string> resume = {
      "sweep", (two / "config.json").string(), "--shard", "0/2", "--no-images", "--resume", "--out", a0.string()};
  const RunResult resumed = run(resume);
  EXPECT_EQ(resumed.exitCode, 0) << resumed.err;
  EXPECT_NE(resumed.out.find("resume: 1 of 1 variants already done"), std::string::npos) << resumed.out;
  EXPECT_NE(resumed.err.find("warning: --resume: the inputs lie at other paths"), std::string::npos) << resumed.err;
  EXPECT_NE(resumed.err.find("scene (interrupted sweep: \"" + sceneOne + "\", this one: \"" + sceneTwo + "\")"),
            std::string::npos)
      << resumed.err;

  // One vertex moved (the first position's x, -0.5 -> -2: base64 "vwAA" is bytes bf 00 00, "wAAA" c0 00 00).
  std::string gltf = hb::testing::readFile(two / "cube.gltf");
  const size_t at = gltf.find("base64,AAAAvwAA");
  ASSERT_NE(at, std::string::npos);
  gltf.replace(at + 11, 4, "wAAA");
  hb::testing::writeFile(two / "cube.gltf", gltf);
  const fs::path moved = sweep(two, 1, "moved");
  const std::string shaA = contextA["scene"]["sha256"];
  const std::string shaMoved = hb::testing::readJson(moved / "results.json")["context"]["scene"]["sha256"];
  ASSERT_NE(shaA, shaMoved);
  const RunResult refused = run({"compare", (a0 / "results.json").string(), (moved / "results.json").string()});
  EXPECT_EQ(refused.exitCode, 2) << refused.out << refused.err;
  EXPECT_NE(refused.err.find("cannot compare: the scenes differ in content: context.scene.sha256 is " + shaA +
                             " in A and " + shaMoved + " in B"),
            std::string::npos)
      << refused.err;
  const RunResult notMerged = run({"merge", a0.string(), moved.string(), "--out", (dir / "merged2").string()});
  EXPECT_EQ(notMerged.exitCode, 2) << notMerged.err;
  EXPECT_NE(notMerged.err.find(shaA), std::string::npos) << notMerged.err;
  EXPECT_NE(notMerged.err.find(shaMoved), std::string::npos) << notMerged.err;
  EXPECT_FALSE(fs::exists(dir / "merged2"));
  const RunResult notResumed = run(resume);
  EXPECT_EQ(notResumed.exitCode, 2) << notResumed.err;
  EXPECT_NE(notResumed.err.find("the scenes differ in content: context.scene.sha256 is " + shaA +
                                " in the interrupted sweep and " + shaMoved + " in this one"),
            std::string::npos)
      << notResumed.err;
}

// The H200 thesis sweep ran with backend auto, which chose compute on every run, on a device whose
// driver offers the ray-tracing pipeline (context.device.rt_backend): the page and the tables say
// compute.
TEST_F(SceneIdentity, TheReportAndTablesNameTheRayTracerThatRanNotTheDevices) {
  const std::string results = (kSource / "results/h200/fleet-35/thesis-whole/results.json.gz").string();
  const json r = hb::testing::readJson(results);
  ASSERT_EQ(r["context"]["device"]["rt_backend"], "pipeline");
  for (const json& run : r["runs"]) {
    ASSERT_EQ(run["backend_choice"]["requested"], "auto");
    ASSERT_EQ(run["backend_choice"]["ran"], "compute");
  }
  const RunResult page = run({"report", results, "--out", (dir / "report.html").string()});
  EXPECT_EQ(page.exitCode, 0) << page.err;
  EXPECT_NE(hb::testing::readFile(dir / "report.html").find("<tr><th>ray tracing</th><td>compute</td></tr>"),
            std::string::npos);
  const RunResult tables = run({"tables", results});
  EXPECT_EQ(tables.exitCode, 0) << tables.err;
  EXPECT_NE(tables.out.find(", ray tracing compute · "), std::string::npos) << tables.out.substr(0, 600);
}

}  // namespace scene_identity_cli_test
