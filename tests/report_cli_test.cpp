// `hybridbench report` and `tables` on committed results: bad input is one line and exit 2, and
// leaves an existing page as it was; a committed results file without its images gives a page that
// says so; the page and the tables say what the results hold and no more (a summary read from them,
// tables only where runs study them and a word where a thesis table is not printed, a comparison
// plot scaled to the timed rows, a roofline that says when a pass ran over its peak).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tool_process.h"

namespace {

using namespace hb::testing;

const std::string kThesis = std::string(HYBRIDBENCH_SOURCE_DIR) + "/results/h100/thesis/results.json.gz";
const std::string kResults = std::string(HYBRIDBENCH_SOURCE_DIR) + "/results/";

// The text between the first `open` at or after `from` and the next `close` after it; "" if absent.
std::string between(const std::string& s, const std::string& open, const std::string& close, size_t from = 0) {
  const size_t a = s.find(open, from);
  if (a == std::string::npos) return "";
  const size_t b = s.find(close, a + open.size());
  return b == std::string::npos ? "" : s.substr(a + open.size(), b - a - open.size());
}

// Every match of `pattern`'s first group in `s`.
std::vector<std::string> allOf(const std::string& s, const std::string& pattern) {
  std::vector<std::string> out;
  const std::regex re(pattern);
  for (auto it = std::sregex_iterator(s.begin(), s.end(), re); it != std::sregex_iterator(); ++it)
    out.push_back((*it)[1].str());
  return out;
}

double medianFrameOf(const nlohmann::json& run) { return run["frame_ms"]["median"].get<double>(); }

class ReportCli : public ToolTest {};

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

// The Fig. 9 table of primary visibility sets compute methods beside the hardware prepass: a sweep
// of the prepass alone (every thesis sweep) has no such table; a sweep of the continuum has it.
TEST_F(ReportCli, PrimaryVisibilityTableOnlyWhereAComputePrimaryRan) {
  const std::string heading = "## Primary visibility";
  const RunResult thesis = run({"tables", kResults + "h200/fleet-35/thesis-whole/results.json.gz"});
  ASSERT_EQ(thesis.exitCode, 0) << thesis.err;
  const nlohmann::json thesisResults = hb::testing::readJson(kResults + "h200/fleet-35/thesis-whole/results.json.gz");
  for (const nlohmann::json& r : thesisResults["runs"])
    ASSERT_EQ(r["primary"]["method"], "hardware") << "the thesis sweep should hold the prepass alone";
  EXPECT_EQ(thesis.out.find(heading), std::string::npos) << thesis.out;
  EXPECT_NE(thesis.out.find("## Table 5.1"), std::string::npos) << thesis.out;

  const std::string continuum = kResults + "h100/3d-rasterization/results.json.gz";
  const RunResult r = run({"tables", continuum});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find(heading), std::string::npos) << r.out;
}

// A results file that no thesis table has rows for says why, in tables.md's words and in the page:
// here every run has range_test=true (the sweep that brings your own glTF), and two have more lights.
TEST_F(ReportCli, ThesisTablesNotPrintedSayWhichRunsAreNotTheThesissFrameAndWhy) {
  const std::string file = kResults + "h200/byo-gltf/sweep/results.json.gz";
  const nlohmann::json results = hb::testing::readJson(file);
  size_t rangeTest = 0;
  std::set<std::string> lightCounts;
  for (const nlohmann::json& r : results["runs"]) {
    rangeTest += r["params"]["range_test"] == true;
    if (r["scene"]["lights"] != 10) lightCounts.insert(r["scene"]["lights"].dump() + " lights (1 run)");
  }
  ASSERT_EQ(rangeTest, results["runs"].size());
  ASSERT_FALSE(lightCounts.empty());
  const RunResult r = run({"tables", file});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(r.out.find("## Table 5.1"), std::string::npos) << r.out;
  const std::string note = between(r.out, "Tables 5.1 and 5.2 (the thesis's) are not printed", "\n");
  ASSERT_FALSE(note.empty()) << "no word on the thesis tables:\n" << r.out;
  EXPECT_NE(note.find("range_test=true (" + std::to_string(rangeTest) + " runs)"), std::string::npos) << note;
  for (const std::string& lights : lightCounts) EXPECT_NE(note.find(lights), std::string::npos) << note;

  const fs::path page = dir / "report.html";
  ASSERT_EQ(run({"report", file, "--out", page.string()}).exitCode, 0);
  EXPECT_NE(readFile(page).find("Tables 5.1 and 5.2 (the thesis"), std::string::npos);
}

// A sweep of the thesis's best variant on the Cornell box (one light) on the device present: its
// scene is not the thesis's (10 lights), so Tables 5.1/5.2 are not printed, and tables.md says why.
TEST_F(ReportCli, TheOneLightCornellBoxGetsNoThesisTableAndTheTablesSayWhy) {
  const fs::path config = fs::path(HYBRIDBENCH_SOURCE_DIR) / "tests/fixtures/report-cornell.json";
  const RunResult r = run({"sweep", config.string(), "--out", (dir / "out").string(), "--no-images"});
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  const nlohmann::json results = hb::testing::readJson(dir / "out" / "results.json");
  ASSERT_EQ(results["runs"].size(), 1u);
  ASSERT_EQ(results["runs"][0]["scene"]["lights"], 1) << "the Cornell box should have one light";
  const std::string tables = readFile(dir / "out" / "tables.md");
  EXPECT_EQ(tables.find("## Table 5.1"), std::string::npos) << tables;
  EXPECT_NE(tables.find("Tables 5.1 and 5.2 (the thesis's) are not printed"), std::string::npos) << tables;
  EXPECT_NE(tables.find("1 light (1 run)"), std::string::npos) << tables;
  EXPECT_NE(r.out.find("1 light (1 run)"), std::string::npos) << "the console's tables do not say it:\n" << r.out;
}

// The B/A plot of two lavapipe sweeps: their passes are "not timed" (a CPU device's pass times mean
// nothing) with intervals of decades; the axis spans the timed rows (the frames) and the threshold
// band, cuts the others, and its tick labels include 1 and do not overlap.
TEST_F(ReportCli, CompareAxisSpansTheTimedRowsAndItsLabelsDoNotOverlap) {
  const std::string a = kResults + "lavapipe/thesis-d56b9c2/results.json.gz",
                    b = kResults + "lavapipe/thesis/results.json.gz";
  const RunResult asJson = run({"compare", a, b, "--format", "json"});
  ASSERT_EQ(asJson.exitCode, 0) << asJson.err;
  const nlohmann::json rows = nlohmann::json::parse(asJson.out)["rows"];
  const fs::path page = dir / "report.html";
  const RunResult r = run({"report", b, "--compare", a, "--out", page.string()});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const std::string html = readFile(page);
  const std::string svg = between(html, "<svg class=\"ratios\"", "</svg>");
  ASSERT_FALSE(svg.empty());
  double lo = 0, hi = 0;
  ASSERT_EQ(std::sscanf(between(svg, "data-axis=\"", "\"").c_str(), "%lf %lf", &lo, &hi), 2) << svg.substr(0, 200);
  double notTimedLo = std::numeric_limits<double>::infinity(), notTimedHi = 0;
  size_t timed = 0;
  for (const nlohmann::json& row : rows) {
    std::vector<double> v;
    for (const char* k : {"ratio", "ci_low", "ci_high"})
      if (row[k].is_number()) v.push_back(row[k].get<double>());
    if (row["verdict"] == "not timed") {
      for (double x : v) notTimedLo = std::min(notTimedLo, x), notTimedHi = std::max(notTimedHi, x);
      continue;
    }
    ++timed;
    for (double x : v) {
      EXPECT_GE(x, lo) << row.dump();
      EXPECT_LE(x, hi) << row.dump();
    }
  }
  ASSERT_GT(timed, 0u);
  ASSERT_TRUE(notTimedLo < lo || notTimedHi > hi) << "these results no longer show a not-timed row beyond the timed";
  // Tick labels: "1" among them; neighbours at least their half widths (11 px sans-serif, about
  // 6.1 px a character) apart.
  const std::regex tick(R"re(<text class="tick" x="([0-9.]+)"[^>]*>([^<]+)</text>)re");
  std::vector<std::pair<double, std::string>> ticks;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), tick); it != std::sregex_iterator(); ++it)
    ticks.push_back({std::stod((*it)[1].str()), (*it)[2].str()});
  ASSERT_GE(ticks.size(), 2u) << svg;
  EXPECT_TRUE(std::any_of(ticks.begin(), ticks.end(), [](const auto& t) { return t.second == "1"; })) << svg;
  std::sort(ticks.begin(), ticks.end());
  for (size_t i = 1; i < ticks.size(); ++i)
    EXPECT_GE(ticks[i].first - ticks[i - 1].first,
              0.5 * 6.1 * double(ticks[i].second.size() + ticks[i - 1].second.size()))
        << ticks[i - 1].second << " and " << ticks[i].second << " overlap";
}

// The lavapipe anti-aliasing sweep: passes whose rate is over the device's peak for their bound (a
// CPU device's ray rate is measured on other rays). Each says the peak is not that pass's, in the
// roofline table, the accuracy report and the plot, where it is drawn at its peak, not above.
TEST_F(ReportCli, ARooflineOverItsPeakSaysThePeakIsNotThePasssAndIsPlottedAtThePeak) {
  const std::string file = kResults + "lavapipe/anti-aliasing-32/results.json.gz";
  const std::string note = "over 100 %: not this pass's peak";
  size_t over = 0;
  const nlohmann::json results = hb::testing::readJson(file);  // named: the loop must not outlive it
  for (const nlohmann::json& r : results["runs"])
    if (r["status"] == "ok")
      for (const auto& [entry, rl] : r["roofline"].items()) over += rl["fraction"].is_number() && rl["fraction"] > 1;
  ASSERT_GT(over, 0u) << "these results no longer have a pass over its peak";

  const RunResult table = run({"tables", file, "--format", "roofline"});
  ASSERT_EQ(table.exitCode, 0) << table.err;
  size_t rowsOver = 0, rowsSaying = 0;
  for (const std::string& pct : allOf(table.out, R"(\| ([0-9.]+ %[^|]*) \| [^|]* \|\n)")) {
    rowsOver += std::stod(pct) > 100;
    rowsSaying += pct.find(note) != std::string::npos;
    EXPECT_EQ(std::stod(pct) > 100, pct.find(note) != std::string::npos) << pct;
  }
  EXPECT_EQ(rowsOver, over);
  EXPECT_EQ(rowsSaying, over);

  const RunResult accuracy = run({"tables", file, "--format", "accuracy"});
  ASSERT_EQ(accuracy.exitCode, 0) << accuracy.err;
  for (const std::string& pct : allOf(accuracy.out, R"(\| [a-z_0-9]+ ([0-9.]+ %[^|]*)\|)"))
    EXPECT_EQ(std::stod(pct) > 100, pct.find(note) != std::string::npos) << pct;

  const RunResult plot = run({"tables", file, "--format", "roofline-svg"});
  ASSERT_EQ(plot.exitCode, 0) << plot.err;
  EXPECT_EQ(allOf(plot.out, R"re(class="(over-peak)")re").size(), over);
  // Every point inside the plot's frame (x 90..640, y 70..540, points spread 6 px either side).
  for (const std::string& y : allOf(plot.out, R"re(<circle cx="[0-9.]+" cy="(-?[0-9.]+)" r="4")re")) {
    EXPECT_GE(std::stod(y), 70.0);
    EXPECT_LE(std::stod(y), 540.0);
  }
  // The legend: each pass's best fraction, and under one over 100 % the line saying what that means.
  const std::vector<std::string> texts = allOf(plot.out, "<text[^>]*>([^<]*)</text>");
  const std::string escapedNote = "over 100 %: not this pass&apos;s peak";
  size_t legendLines = 0;
  for (size_t i = 0; i + 1 < texts.size(); ++i) {
    const size_t upTo = texts[i].find(": up to ");
    if (upTo == std::string::npos) continue;
    ++legendLines;
    const double pct = std::stod(texts[i].substr(upTo + 8));
    EXPECT_EQ(pct > 100, texts[i + 1] == escapedNote) << texts[i] << " / " << texts[i + 1];
  }
  EXPECT_GT(legendLines, 0u);
}

// The page starts with the story the results tell: the fastest variant (the least median frame
// time), the most accurate one with what its accuracy costs against the fastest, and the Pareto
// front, the same as the accuracy report's (its Pareto column), from fast to accurate.
TEST_F(ReportCli, TheSummarySaysTheFastestTheMostAccurateAndTheFrontOfTheAccuracyReport) {
  const std::string file = kResults + "h200/fleet-35/thesis-whole/results.json.gz";
  const nlohmann::json results = hb::testing::readJson(file);
  std::string fastest;
  double fastestMs = std::numeric_limits<double>::infinity();
  for (const nlohmann::json& r : results["runs"])
    if (medianFrameOf(r) < fastestMs) fastestMs = medianFrameOf(r), fastest = r["name"].get<std::string>();
  const RunResult accuracy = run({"tables", file, "--format", "accuracy"});
  ASSERT_EQ(accuracy.exitCode, 0) << accuracy.err;
  std::set<std::string> front;
  for (const std::string& name : allOf(accuracy.out, R"(\n\| ([^|]+) \|[^\n]*\| \*\*yes\*\* \|)")) front.insert(name);
  ASSERT_GE(front.size(), 2u) << accuracy.out;

  const fs::path page = dir / "report.html";
  ASSERT_EQ(run({"report", file, "--out", page.string()}).exitCode, 0);
  const std::string html = readFile(page);
  const size_t summaryAt = html.find("<section id=\"summary\">");
  ASSERT_NE(summaryAt, std::string::npos) << "no summary";
  EXPECT_LT(summaryAt, html.find("<section id=\"context\">")) << "the summary is not at the top";
  const std::string summary = between(html, "<section id=\"summary\">", "</section>");
  EXPECT_NE(summary.find("Fastest: <b>" + fastest + "</b>"), std::string::npos) << summary;
  const std::string frontItem = between(summary, "<li class=\"front\">", "</li>");
  const std::vector<std::string> chain = allOf(frontItem, "<b>([^<]+)</b>");
  EXPECT_EQ(std::set<std::string>(chain.begin(), chain.end()), front) << frontItem;
  ASSERT_FALSE(chain.empty());
  // From fast to accurate: the front's last is the most accurate, its first the fastest.
  EXPECT_NE(summary.find("Most accurate: <b>" + chain.back() + "</b>"), std::string::npos) << summary;
  EXPECT_EQ(chain.front(), fastest);
}

// tables --format built: the frame's built resources alone, one row a run and resource (the
// committed H200 sweep of the tracer study builds trace_bvh in every run, and the TLAS where the
// driver's tracer runs too); a file whose runs built nothing is one line and exit 2.
TEST_F(ReportCli, TablesFormatBuiltListsWhatEachRunBuiltOrSaysThereIsNone) {
  const std::string file = kResults + "h200/tracer-51/speculative/bvh-width-H/results.json.gz";
  const nlohmann::json results = hb::testing::readJson(file);
  size_t built = 0;
  for (const nlohmann::json& r : results["runs"])
    for (const auto& [name, res] : r["frame_resources"].items()) built += res.contains("build_ms");
  ASSERT_GT(built, 0u);
  const RunResult table = run({"tables", file, "--format", "built"});
  ASSERT_EQ(table.exitCode, 0) << table.err;
  EXPECT_EQ(allOf(table.out, R"(\n\| [^|]+ \| (trace_bvh|tlas|[a-z_.]+) \| [a-z_]+ \| [0-9.]+ \|)").size(), built)
      << table.out;
  const RunResult none =
      run({"tables", kResults + "h200/continuum-32/ab3-3588072/results.json.gz", "--format", "built"});
  EXPECT_EQ(none.exitCode, 2);
  EXPECT_NE(none.err.find("no run records a resource built"), std::string::npos) << none.err;
  EXPECT_EQ(std::count(none.err.begin(), none.err.end(), '\n'), 1) << none.err;
}

}  // namespace
