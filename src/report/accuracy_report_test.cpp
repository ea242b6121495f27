#include "report/accuracy_report.h"

#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "base/errors.h"
#include "base/input_file.h"
#include "report/xml_test_util.h"

namespace hb {
namespace {

using testing::xmlProblem;

using nlohmann::json;

json run(const std::string& name, double ms, double imageError) {
  return {{"name", name},
          {"status", "ok"},
          {"frame_ms", {{"median", ms}}},
          {"rays", {{"traced", 120}, {"oracle", 100}, {"efficiency", 100.0 / 120}}},
          {"culling", {{"false_positive_rate", 0.25}, {"false_negatives", 0}}},
          {"accuracy",
           {{"image_error", imageError},
            {"world_pos_rel_error", 1e-7},
            {"normal_angular_error_deg", 1.5},
            {"normal_image_error", 0.004},
            {"shadow_mismatches", {{"pairs_compared", 1000}, {"wrongly_dark", 3}, {"wrongly_lit", 1}}}}}};
}

json resultsWith(std::vector<json> runs) {
  return {{"schema_version", 1},
          {"context",
           {{"device", {{"name", "Test <GPU> & Co"}}}, {"resolution", {64, 32}}, {"config", {{"name", "unit"}}}}},
          {"runs", runs}};
}

// Hand-made sweep (time ms, image error):
//   A (10, 0.00)  front: nothing else has error ≤ 0 and time ≤ 10 (G is slower).
//   B ( 5, 0.01)  front: only C is faster, and C has more error.
//   C ( 4, 0.02)  front: the fastest ok run.
//   D ( 6, 0.01)  dominated by B (faster, equal error).
//   E ( 5, 0.01)  front: identical to B; neither is strictly better, so both stay.
//   F ( 1, 0.00)  status error: would dominate everything if counted, but failed runs never do.
//   G (12, 0.00)  dominated by A (faster, equal error).
json handMade() {
  json f = run("F", 1, 0);
  f["status"] = "error";
  f["error"] = "device lost | retry";
  return resultsWith({run("A", 10, 0), run("B", 5, 0.01), run("C", 4, 0.02), run("D", 6, 0.01), run("E", 5, 0.01), f,
                      run("G", 12, 0)});
}

std::vector<std::string> frontNames(const AccuracyFront& f) {
  std::vector<std::string> names;
  for (const AccuracyPoint& p : f.points)
    if (p.onFront) names.push_back(p.name);
  return names;
}

// Cells of the Markdown table row that starts with "| name |".
std::vector<std::string> rowCells(const std::string& md, const std::string& name) {
  const size_t start = md.find("\n| " + name + " |");
  if (start == std::string::npos) return {};
  const std::string line = md.substr(start + 1, md.find('\n', start + 1) - start - 1);
  std::vector<std::string> cells;
  size_t pos = 1;
  while (pos < line.size()) {
    size_t next = pos;
    while (next < line.size() && !(line[next] == '|' && line[next - 1] != '\\')) ++next;
    std::string c = line.substr(pos, next - pos);
    c.erase(0, c.find_first_not_of(' '));
    c.erase(c.find_last_not_of(' ') + 1);
    cells.push_back(c);
    pos = next + 1;
  }
  return cells;
}

size_t count(const std::string& s, const std::string& what) {
  size_t n = 0;
  for (size_t pos = 0; (pos = s.find(what, pos)) != std::string::npos; pos += what.size()) ++n;
  return n;
}

TEST(AccuracyReport, ParetoFrontIsTheHandComputedSet) {
  const AccuracyFront f = accuracyFront(handMade());
  EXPECT_EQ(f.measure, AccuracyMeasure::ImageError);
  EXPECT_EQ(frontNames(f), (std::vector<std::string>{"A", "B", "C", "E"}));
}

TEST(AccuracyReport, FailedRunsAreListedAndNeverOnTheFront) {
  const std::string md = accuracyReportMarkdown(handMade());
  const std::vector<std::string> cells = rowCells(md, "F");
  ASSERT_FALSE(cells.empty()) << md;
  EXPECT_EQ(cells[1], "failed");
  EXPECT_EQ(cells.back(), "—");
  EXPECT_NE(md.find("- F: device lost \\| retry"), std::string::npos) << md;
  EXPECT_EQ(rowCells(md, "A").back(), "**yes**");
  EXPECT_EQ(rowCells(md, "D").back(), "no");
  // Rows in results order.
  EXPECT_LT(md.find("| A |"), md.find("| B |"));
  EXPECT_LT(md.find("| F |"), md.find("| G |"));
}

TEST(AccuracyReport, MissingFieldsPrintADashNeverAFigure) {
  json bare = {{"name", "bare"},
               {"status", "ok"},
               {"frame_ms", {{"median", 3.0}}},
               {"rays", {{"traced", 100}, {"oracle", 100}}}};
  const std::string md = accuracyReportMarkdown(resultsWith({run("full", 5, 0.01), bare}));
  const std::vector<std::string> cells = rowCells(md, "bare");
  // | name | frame | traced | eff | fp | fp geometry | fn | normal° | normal img | world | image | dark
  // | lit | pareto
  ASSERT_EQ(cells.size(), 14u) << md;
  EXPECT_EQ(cells[1], "3.000");
  EXPECT_EQ(cells[2], "100");
  for (size_t c = 3; c <= 12; ++c) EXPECT_EQ(cells[c], "—") << "column " << c;
  // "bare" lacks image error and shadow mismatches, so the sweep falls back to the ray deficit,
  // which both runs carry: full has traced 120 ≥ oracle 100 → deficit 0 (surplus is not error),
  // bare 0 too; bare is faster, so it alone is on the front.
  EXPECT_EQ(cells[13], "**yes**");
  EXPECT_EQ(rowCells(md, "full").back(), "no");
  EXPECT_NE(md.find("ray deficit"), std::string::npos);
}

TEST(AccuracyReport, MeasureFallsBackToShadowMismatchesThenRayDeficit) {
  json a = run("a", 5, 0), b = run("b", 4, 0);
  b["accuracy"].erase("image_error");
  // a: (3 + 1) / 1000 = 0.004; b the same. Equal error, b faster → b alone on the front.
  AccuracyFront f = accuracyFront(resultsWith({a, b}));
  EXPECT_EQ(f.measure, AccuracyMeasure::ShadowMismatchRate);
  EXPECT_DOUBLE_EQ(f.points[0].error, 0.004);
  EXPECT_EQ(frontNames(f), (std::vector<std::string>{"b"}));

  b["accuracy"].erase("shadow_mismatches");
  b["rays"]["traced"] = 90;  // 10 of 100 needed rays at least were not traced
  f = accuracyFront(resultsWith({a, b}));
  EXPECT_EQ(f.measure, AccuracyMeasure::RayDeficit);
  EXPECT_DOUBLE_EQ(f.points[0].error, 0.0);  // 120 traced ≥ 100 needed: no deficit
  EXPECT_DOUBLE_EQ(f.points[1].error, 0.1);
  EXPECT_EQ(frontNames(f), (std::vector<std::string>{"a", "b"}));  // a more accurate, b faster

  b.erase("rays");
  f = accuracyFront(resultsWith({a, b}));
  EXPECT_EQ(f.measure, AccuracyMeasure::None);
  EXPECT_TRUE(frontNames(f).empty());
}

TEST(AccuracyReport, SvgIsWellFormedWithOneCirclePerOkRun) {
  const std::string svg = accuracyReportSvg(handMade());
  EXPECT_EQ(xmlProblem(svg), "");
  EXPECT_EQ(count(svg, "<circle"), 6u);  // 7 runs, F failed
  EXPECT_NE(svg.find("Test &lt;GPU&gt; &amp; Co, 64×32"), std::string::npos);
  EXPECT_NE(svg.find("<path"), std::string::npos);  // the front's staircase
}

TEST(AccuracyReport, RejectsAFileThatIsNotResults) {
  EXPECT_THROW(accuracyReportMarkdown(json{{"runs", 3}}), InputError);
  EXPECT_THROW(accuracyReportSvg(json::array()), InputError);
}

TEST(AccuracyReport, RendersTheCommittedH100ThesisSweep) {
  // Committed gzipped (docs/results-format.md "Committed results"), read as the tool reads it.
  const json results =
      json::parse(readInputText(HYBRIDBENCH_SOURCE_DIR "/results/h100/thesis/results.json.gz", "a results file"));
  std::string md, svg;
  ASSERT_NO_THROW(md = accuracyReportMarkdown(results));
  ASSERT_NO_THROW(svg = accuracyReportSvg(results));
  EXPECT_EQ(xmlProblem(svg), "");
  size_t ok = 0;
  for (const json& r : results["runs"]) ok += r["status"] == "ok";
  EXPECT_EQ(count(svg, "<circle"), ok);
  EXPECT_FALSE(frontNames(accuracyFront(results)).empty());
  if (const char* dump = std::getenv("HB_ACCURACY_REPORT_DUMP")) {
    std::ofstream(std::string(dump) + ".svg") << svg;
    std::ofstream(std::string(dump) + ".md") << md;
  }
}

// Dozens of runs drawn at nearly the same spot (every error 0): the number labels step aside a
// bounded number of times (this sweep once hung the label placement).
TEST(AccuracyReport, RendersTheCommittedManyLightsSweeps) {
  for (const char* which : {"dense", "small"}) {
    const json results = json::parse(
        readInputText(std::string(HYBRIDBENCH_SOURCE_DIR "/results/h200/many-lights/") + which + "/results.json.gz",
                      "a results file"));
    std::string svg;
    ASSERT_NO_THROW(svg = accuracyReportSvg(results));
    EXPECT_EQ(xmlProblem(svg), "") << which;
    size_t ok = 0;
    for (const json& r : results["runs"]) ok += r["status"] == "ok";
    EXPECT_EQ(count(svg, "<circle"), ok) << which;
  }
}

}  // namespace
}  // namespace hb
