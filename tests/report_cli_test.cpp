// `hybridbench report`: bad input is one line and exit 2, and leaves an existing page as it was;
// a committed results file without its images gives a page that says so.
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tool_process.h"

#ifndef HYBRIDBENCH_SOURCE_DIR
#error "HYBRIDBENCH_SOURCE_DIR must name the source tree"
#endif

namespace {

namespace fs = std::filesystem;
using hb::testing::readFile;
using hb::testing::RunResult;
using hb::testing::writeFile;

const std::string kThesis = std::string(HYBRIDBENCH_SOURCE_DIR) + "/results/h100/thesis/results.json";

class ReportCli : public hb::testing::ToolTest {};

TEST_F(ReportCli, BadInputIsOneLineNamingItExitTwoAndLeavesThePageAsItWas) {
  const fs::path page = dir / "report.html";
  writeFile(page, "the earlier page");
  writeFile(dir / "broken.json", "{\"schema_version\": 1, \"runs\": [");
  writeFile(dir / "render.json", "{\"passes_run\": []}");
  nlohmann::json otherScene = hb::testing::readJson(kThesis);
  otherScene["context"]["scene"]["sha256"] = "0000";
  writeFile(dir / "other-scene.json", otherScene.dump());
  fs::create_directories(dir / "folder");

  struct Case {
    std::vector<std::string> args;
    std::string named;  // what the line must name
  };
  const std::vector<Case> cases = {
      {{"report", (dir / "missing.json").string(), "--out", page.string()}, "missing.json"},
      {{"report", (dir / "broken.json").string(), "--out", page.string()}, "not valid JSON"},
      {{"report", (dir / "render.json").string(), "--out", page.string()}, "is a render.json"},
      {{"report", kThesis, "--compare", (dir / "other-scene.json").string(), "--out", page.string()}, "sha256"},
      {{"report", kThesis, "--out", (dir / "folder").string()}, "is a folder"},
      {{"report", kThesis, "--out", (dir / "no-such-folder" / "report.html").string()}, "does not exist"},
  };
  for (const Case& c : cases) {
    const RunResult r = run(c.args);
    EXPECT_EQ(r.exitCode, 2) << c.named << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find(c.named), std::string::npos) << r.err;
    EXPECT_EQ(readFile(page), "the earlier page") << c.named;
  }
  EXPECT_FALSE(fs::exists(dir / "no-such-folder"));
}

TEST_F(ReportCli, ResultsCopiedWithoutTheirImagesSaySoInsteadOfBrokenImages) {
  const fs::path page = dir / "report.html";
  const RunResult r = run({"report", kThesis, "--out", page.string()});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const std::string html = readFile(page);
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_EQ(html.find("<img"), std::string::npos);
  EXPECT_NE(html.find("no images beside the results"), std::string::npos);
}

}  // namespace
