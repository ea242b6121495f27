// `hybridbench history` as a user runs it: exit 1 with --gate only when a series' newest segment is
// slower, exit 0 without --gate, one refusal line and exit 2 for bad input, the --json and --html
// files written, and the committed results read from their folders.
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tool_process.h"

// A named namespace: the unity build puts this file beside others with helpers of the same names.
namespace history_cli_test {

using namespace hb::testing;

class HistoryCli : public ToolTest {
 protected:
  // Folder run<i>/results.json per frame median: revision r<i>, swept on day i + 1, one run "best"
  // with a "shading" pass at half the frame.
  void writeSeries(const std::vector<double>& frameMs) {
    for (size_t i = 0; i < frameMs.size(); ++i) {
      const std::string day = (i + 1 < 10 ? "0" : "") + std::to_string(i + 1);
      const nlohmann::json results = {{"schema_version", 1},
                                      {"context",
                                       {{"tool", {{"git", "r" + std::to_string(i)}}},
                                        {"host", {{"date", "2026-11-" + day + "T00:00:00Z"}}},
                                        {"device", {{"name", "Test GPU"}, {"type", "discrete"}}},
                                        {"scene", {{"sha256", "abc"}}},
                                        {"resolution", {64, 64}},
                                        {"config", {{"name", "thesis"}}}}},
                                      {"runs",
                                       {{{"name", "best"},
                                         {"status", "ok"},
                                         {"frame_ms", {{"median", frameMs[i]}}},
                                         {"passes", {{"shading", {{"median", frameMs[i] / 2}}}}}}}}};
      fs::create_directories(dir / ("run" + std::to_string(i)));
      std::ofstream(dir / ("run" + std::to_string(i)) / "results.json") << results.dump();
    }
  }
};

// Levels 4, 4.01, 3.99, ...: within 0.25 % of 4 ms.
std::vector<double> level(double ms, size_t n) {
  std::vector<double> v;
  for (size_t i = 0; i < n; ++i) v.push_back(ms * (1 + 0.0025 * double(int(i % 3) - 1)));
  return v;
}

TEST_F(HistoryCli, GateExitsOneOnlyWhenTheNewestSegmentIsSlower) {
  std::vector<double> ms = level(4.0, 6);
  for (double v : level(4.6, 6)) ms.push_back(v);
  writeSeries(ms);
  const RunResult gated = run({"history", dir.string(), "--gate"});
  EXPECT_EQ(gated.exitCode, 1) << gated.out << gated.err;
  EXPECT_NE(gated.out.find("| r5 → r6 |"), std::string::npos) << gated.out;
  EXPECT_NE(gated.out.find("- slower: best / frame"), std::string::npos) << gated.out;
  // Without --gate the same finding is printed and the exit is 0.
  EXPECT_EQ(run({"history", dir.string()}).exitCode, 0);
}

TEST_F(HistoryCli, AFasterNewestSegmentDoesNotGate) {
  std::vector<double> ms = level(4.6, 6);
  for (double v : level(4.0, 6)) ms.push_back(v);
  writeSeries(ms);
  const RunResult r = run({"history", dir.string(), "--gate"});
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("| r5 → r6 |"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("regression (newest segment slower by > 5 %): no"), std::string::npos) << r.out;
}

TEST_F(HistoryCli, WritesItsJsonAndAPageWithAPlotPerChangedSeries) {
  std::vector<double> ms = level(4.0, 6);
  for (double v : level(4.6, 6)) ms.push_back(v);
  writeSeries(ms);
  const fs::path out = dir / "out";
  fs::create_directories(out);
  const RunResult r = run({"history", (dir / "run0").string(), dir.string(), "--json", (out / "h.json").string(),
                           "--html", (out / "h.html").string()});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const nlohmann::json j = readJson(out / "h.json");
  ASSERT_FALSE(j.is_discarded());
  EXPECT_EQ(j["schema_version"], 1);
  EXPECT_EQ(j["files"], 12);  // run0 named twice, read once
  ASSERT_EQ(j["series"].size(), 2u);
  EXPECT_EQ(j["series"][0]["points"].size(), 12u);
  ASSERT_EQ(j["series"][0]["changes"].size(), 1u);  // (operator[] past the end of a const json is undefined)
  EXPECT_EQ(j["series"][0]["changes"][0]["revision_after"], "r6");
  const std::string html = readFile(out / "h.html");
  size_t plots = 0, circles = 0;
  for (size_t at = html.find("<svg class=\"series\""); at != std::string::npos;
       at = html.find("<svg class=\"series\"", at + 1))
    ++plots;
  for (size_t at = html.find("<circle"); at != std::string::npos; at = html.find("<circle", at + 1)) ++circles;
  EXPECT_EQ(plots, 2u);
  EXPECT_EQ(circles, 24u);
  EXPECT_NE(html.find("class=\"change\""), std::string::npos);
  EXPECT_NE(html.find("r6, 2026-11-07T00:00:00Z, "), std::string::npos);  // a circle's title
}

TEST_F(HistoryCli, BadInputIsOneLineAndExitTwo) {
  expectRefused({"history", (dir / "missing").string()}, {"missing", "no such file or folder"});
  fs::create_directories(dir / "empty");
  expectRefused({"history", (dir / "empty").string()}, {"empty", "holds no results.json"});
  std::ofstream(dir / "empty" / "notes.json") << "{\"hello\": 1}";
  expectRefused({"history", (dir / "empty" / "notes.json").string(), (dir / "empty" / "notes.json").string()},
                {"notes.json", "not a schema_version 1 results file"});
  writeSeries({4.0});
  expectRefused({"history", dir.string()}, {"one results file has no history"});
  writeSeries({4.0, 4.0, 4.0});
  expectRefused({"history", dir.string(), "--alpha", "2"}, {"--alpha 2"});
  expectRefused({"history", dir.string(), "--json", (dir / "nowhere" / "h.json").string()}, {"nowhere"});
}

TEST_F(HistoryCli, ReadsTheCommittedResultsFromTheirFolders) {
  const fs::path h100 = fs::path(HYBRIDBENCH_SOURCE_DIR) / "results/h100";
  const RunResult r = run({"history", h100.string(), "--json", (dir / "h.json").string()});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const nlohmann::json j = readJson(dir / "h.json");
  ASSERT_FALSE(j.is_discarded());
  // The thesis group: six sweeps at five revisions, 9 variants.
  bool thesis = false;
  for (const nlohmann::json& g : j["groups"]) thesis |= g["config"] == "thesis" && g["resolution"] == "1920x1080";
  EXPECT_TRUE(thesis);
  for (const nlohmann::json& s : j["series"])
    if (j["groups"][s["group"].get<size_t>()]["config"] == "thesis" && s["pass"] == "frame") {
      EXPECT_EQ(s["points"].size(), 6u);
      EXPECT_LT(s["points"][0]["date"].get<std::string>(), s["points"][5]["date"].get<std::string>());
    }
}

}  // namespace history_cli_test
