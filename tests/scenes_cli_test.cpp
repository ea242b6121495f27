// End-to-end tests of scenes/ and `hybridbench scene list`: the listing names every built-in scene
// and every file in scenes/; every committed file loads and renders on the present device (lavapipe
// here, validation layers on); the exported built-ins in scenes/ are what the exporter writes today.
// The Khronos validator's checks of the same files are tests/gltf_validator_test.sh.
#include <algorithm>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "base/image_io.h"
#include "scene/hard_cases.h"
#include "tool_process.h"

namespace {

using namespace hb::testing;

const fs::path kScenes = fs::path(HYBRIDBENCH_SOURCE_DIR) / "scenes";

// Built-in scenes that scenes/ leaves out (regenerate.sh): ~262k triangles each, megabytes as glTF,
// and the ceiling scenes (microbench-dense is 0.35 MB as .glb, microbench-tiny 262k triangles).
const std::set<std::string> kNotCommitted = {"atrium", "microbench-262144", "microbench-dense", "microbench-tiny"};

bool isGltf(const fs::path& p) { return p.extension() == ".gltf" || p.extension() == ".glb"; }

// The committed scene files: the .gltf/.glb at the top of scenes/ (subfolders hold downloads,
// such as scenes/sponza/ from scripts/fetch-sponza.sh, which git ignores).
std::vector<fs::path> committedSceneFiles() {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(kScenes))
    if (entry.is_regular_file() && isGltf(entry.path())) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

class Scenes : public ToolTest {};

TEST_F(Scenes, ThereAreCommittedFilesAndTheCornellBoxIsOne) {
  const std::vector<fs::path> files = committedSceneFiles();
  EXPECT_GE(files.size(), 13u);
  EXPECT_NE(std::find(files.begin(), files.end(), kScenes / "cornell-box.gltf"), files.end());
  for (const fs::path& f : files) EXPECT_LT(fs::file_size(f), 200u * 1024u) << f << ": keep scenes/ small";
}

TEST_F(Scenes, ListNamesEveryBuiltinAndEveryFileInScenes) {
  std::vector<std::vector<std::string>> calls = {{"scene", "list", "--dir", kScenes.string()}};
  // Without --dir, in the build directory (which has no scenes/ of its own), the listing reads the
  // scenes/ of the repository the executable sits in: checked when the build is inside the tree.
  const std::string binary = fs::weakly_canonical(HYBRIDBENCH_BINARY).string();
  if (binary.rfind(fs::weakly_canonical(HYBRIDBENCH_SOURCE_DIR).string() + "/", 0) == 0)
    calls.push_back({"scene", "list"});
  for (const auto& args : calls) {
    SCOPED_TRACE(args.size() == 2 ? "scene list" : "scene list --dir");
    const RunResult r = run(args);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_TRUE(r.err.empty()) << r.err;
    for (const std::string& name : hb::allSceneNames())
      EXPECT_NE(r.out.find("\n  " + name + " "), std::string::npos) << "no row for built-in " << name << ":\n" << r.out;
    for (const fs::path& file : committedSceneFiles())
      EXPECT_NE(r.out.find("/" + file.filename().string() + " "), std::string::npos) << "no row for " << file << ":\n"
                                                                                     << r.out;
    EXPECT_EQ(r.out.find("does not load"), std::string::npos) << r.out;
  }
}

TEST_F(Scenes, ListJsonGivesCountsAndWhatTheCornellBoxCallsFor) {
  const RunResult r = run({"scene", "list", "--dir", kScenes.string(), "--json"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(fs::weakly_canonical(j["scenes_dir"].get<std::string>()), fs::weakly_canonical(kScenes));

  const std::vector<std::string> names = hb::allSceneNames();
  ASSERT_EQ(j["builtin"].size(), names.size());
  std::map<std::string, nlohmann::json> builtins;
  for (size_t i = 0; i < names.size(); ++i) {
    const nlohmann::json& b = j["builtin"][i];
    EXPECT_EQ(b["name"], names[i]);
    EXPECT_FALSE(b["description"].get<std::string>().empty()) << names[i] << " has no description";
    EXPECT_GT(b["triangles"].get<uint64_t>(), 0u) << names[i];
    EXPECT_GE(b["lights"].get<size_t>(), 1u) << names[i];
    builtins[names[i]] = b;
  }

  std::map<std::string, nlohmann::json> files;  // by file name
  for (const nlohmann::json& f : j["files"]) files[fs::path(f["path"].get<std::string>()).filename().string()] = f;
  for (const fs::path& committed : committedSceneFiles()) {
    const std::string name = committed.filename().string();
    ASSERT_TRUE(files.count(name)) << name << " is not listed";
    const nlohmann::json& f = files[name];
    ASSERT_FALSE(f.contains("error")) << name << ": " << f["error"];
    EXPECT_EQ(f["bytes"].get<uintmax_t>(), fs::file_size(committed)) << name;
    // An exported built-in has the built-in's counts.
    const std::string stem = committed.stem().string();
    if (builtins.count(stem)) {
      EXPECT_EQ(f["triangles"], builtins[stem]["triangles"]) << name;
      EXPECT_EQ(f["lights"], builtins[stem]["lights"]) << name;
    }
  }
  const nlohmann::json& box = files["cornell-box.gltf"];
  EXPECT_EQ(box["triangles"].get<uint64_t>(), 34u);
  EXPECT_EQ(box["lights"].get<size_t>(), 1u);
  EXPECT_TRUE(box["ambient"].get<bool>());
  for (const char* effect : {"shadows", "ambient_occlusion", "indirect"})
    EXPECT_TRUE(box["effects"].contains(effect) && box["effects"][effect] != false) << effect << ": " << box["effects"];
}

TEST_F(Scenes, ListDirThatIsNotAFolderIsOneLineNamingIt) {
  const std::string missing = (dir / "no-such-folder").string();
  const RunResult r = run({"scene", "list", "--dir", missing});
  EXPECT_EQ(r.exitCode, 2) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("--dir " + missing), std::string::npos) << r.err;
}

// Every committed file on the present device: exit 0 with validation on, and a colour image that
// is not one flat colour (something was drawn and lit).
TEST_F(Scenes, EveryFileLoadsAndRendersANonEmptyImage) {
  for (const fs::path& file : committedSceneFiles()) {
    SCOPED_TRACE(file.string());
    const fs::path out = dir / file.stem();
    const RunResult r = run({"render", "--scene", file.string(), "--size", "64x48", "--out", out.string()});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const hb::ImageRGBA8 color = hb::readPng(out / "color.png");
    ASSERT_EQ(color.width, 64u);
    ASSERT_EQ(color.height, 48u);
    std::set<uint32_t> colours;
    for (size_t p = 0; p + 3 < color.px.size(); p += 4)
      colours.insert(uint32_t(color.px[p]) << 16 | uint32_t(color.px[p + 1]) << 8 | color.px[p + 2]);
    EXPECT_GE(colours.size(), 2u) << "color.png is one flat colour";
    const nlohmann::json report = nlohmann::json::parse(readFile(out / "render.json"));
    if (file.filename() == "cornell-box.gltf")  // the effects its extras call for run
      for (const char* effect : {"shadows", "ambient_occlusion", "indirect"}) {
        EXPECT_TRUE(report["effects"][effect]["runs"].get<bool>()) << effect << ": " << report["effects"][effect];
        EXPECT_EQ(report["effects"][effect]["source"], "scene") << effect;
      }
  }
}

// scenes/ holds the built-ins as the exporter writes them now, so a change to a hard case or to
// the exporter shows here until scenes/regenerate.sh has been run.
TEST_F(Scenes, CommittedBuiltinsAreWhatTheExporterWritesToday) {
  for (const std::string& name : hb::allSceneNames()) {
    if (kNotCommitted.count(name)) continue;
    SCOPED_TRACE(name);
    std::vector<fs::path> committed;
    for (const char* ext : {".gltf", ".glb"})
      if (fs::exists(kScenes / (name + ext))) committed.push_back(kScenes / (name + ext));
    ASSERT_EQ(committed.size(), 1u) << "scenes/ should hold " << name << " as one .gltf or .glb (scenes/regenerate.sh)";
    const fs::path fresh = dir / committed[0].filename();
    const RunResult r = run({"scene", "export", name, fresh.string()});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_TRUE(readFile(fresh) == readFile(committed[0]))
        << committed[0] << " differs from what `hybridbench scene export " << name
        << "` writes today; run scenes/regenerate.sh";
  }
}

}  // namespace
