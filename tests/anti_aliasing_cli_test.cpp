// The anti-aliasing study (3D rasterization paper, Fig. 8) from a real sweep on the device present
// (lavapipe in CI): configs/anti-aliasing-ci.json through the built hybridbench with
// HYBRIDBENCH_VALIDATION=1. Held: every run succeeds; each compute run's sample planes hold as many
// samples as its mode stores and cover each sample exactly as the CPU rasterization does at that
// position; every AA mode lowers the image error against the supersampled reference below its
// variant without AA (the error that is left is shading once per pixel, which the reference does
// per sample); the anti-aliasing table has one row per run with "vs no AA" 1.00x on the runs
// without AA. No time is asserted: 3 frames on a CPU device measure nothing. About 60 s on lavapipe.
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tool_process.h"

namespace {

using namespace hb::testing;

const fs::path kAaCiConfig = fs::path(HYBRIDBENCH_SOURCE_DIR) / "configs/anti-aliasing-ci.json";

class AntiAliasingSweep : public ToolTest {};

TEST_F(AntiAliasingSweep, EveryModeCoversItsSamplesExactlyAndLowersTheImageError) {
  const json config = readJson(kAaCiConfig);
  ASSERT_TRUE(config.is_object() && config.contains("variants")) << kAaCiConfig;
  const fs::path out = dir / "sweep";
  const RunResult r = run({"sweep", kAaCiConfig.string(), "--out", out.string(), "--no-images"});
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  const json results = readJson(out / "results.json");
  ASSERT_TRUE(results.is_object() && results.contains("runs"));
  std::map<std::string, const json*> byName;
  for (const json& run : results["runs"]) {
    ASSERT_EQ(run.value("status", "?"), "ok") << run.value("name", "?") << ": " << run.value("error", json()).dump();
    byName[run["name"].get<std::string>()] = &run;
  }
  const std::map<std::string, int> stored = {{"msaa4", 4}, {"msaa16", 16}, {"csaa-4-12", 4}};
  size_t aaRuns = 0;
  for (const json& run : results["runs"]) {
    const std::string name = run["name"], aa = run["params"].value("aa", "none");
    const json& flip = run["accuracy"]["image_error_flip"];
    EXPECT_NE(flip.value("reference", "").find("16 samples a pixel"), std::string::npos) << name << ": " << flip;
    if (aa == "none") continue;
    ++aaRuns;
    // The same variant without AA: its name with the mode replaced by "aa none".
    const std::string base = name.substr(0, name.find(", ")) + ", aa none";
    ASSERT_TRUE(byName.count(base)) << "no run " << base;
    const double mine = run["accuracy"]["image_error"], without = (*byName[base])["accuracy"]["image_error"];
    EXPECT_LT(mine, without) << name << " against " << base;
    if (run["params"]["primary"] == "hardware") continue;  // multisampled in the raster pipeline
    const json& a = run["primary"]["aa"];
    EXPECT_EQ(a.value("stored_samples", -1), stored.at(aa)) << name;
    EXPECT_EQ(a.value("coverage_samples", -1), aa == "msaa4" ? 4 : 16) << name;
    EXPECT_EQ(a["sample_coverage_check"].value("holes", -1), 0) << name;
    EXPECT_EQ(a["sample_coverage_check"].value("double_covers", -1), 0) << name;
    EXPECT_GT(a.value("sample_triangle_setups", 0), 0) << name;
    EXPECT_GT(a.value("sample_atomics", 0), 0) << name;
  }
  EXPECT_EQ(aaRuns, 4u);

  // The table, in tables.md and accuracy.md alike: one row per run; printed for the log.
  const std::string heading = "## Anti-aliasing — what accuracy costs in time (3D rasterization paper, Fig. 8)";
  const std::vector<std::string> rows = markdownTableRows(readFile(out / "tables.md"), heading);
  std::cout << heading << " on this device:\n";
  for (const std::string& line : rows) std::cout << line << "\n";
  ASSERT_EQ(rows.size(), 2 + config["variants"].size()) << "header, rule and one row per variant";
  EXPECT_EQ(markdownTableRows(readFile(out / "accuracy.md"), heading), rows);
  for (size_t i = 2; i < rows.size(); ++i) {
    if (rows[i].find("| none |") != std::string::npos) {
      EXPECT_NE(rows[i].find("| 1.00x |"), std::string::npos) << "a run without AA is its own baseline: " << rows[i];
    }
  }
}

}  // namespace
