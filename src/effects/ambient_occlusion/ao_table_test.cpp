#include "effects/ambient_occlusion/ao_table.h"

#include <gtest/gtest.h>

#include "report/accuracy_report.h"
#include "report/results_fixture_test_util.h"

namespace hb {
namespace {

using nlohmann::json;

json aoRun(const char* name, double frameMs, json ao, json passes) {
  return testing::effectRun(name, frameMs, "ambient_occlusion", std::move(ao), std::move(passes));
}

json results() {
  const json ldm = {{"method", "ldm"},
                    {"directions", 512},
                    {"ldm_resolution", 200},
                    {"memory_bytes", {{"ldm_links", 2.0 * 1048576}}},
                    {"ldm",
                     {{"exact_bytes", 1.9 * 1048576},
                      {"overflow", 0},
                      {"nodes_per_pixel", {{"mean", 2.12}, {"p99", 11}, {"max", 27}}}}},
                    {"vs_raytraced", {{"mae", 0.0104}, {"bias", 0.006}}},
                    {"vs_reference", {{"mae", 0.02}, {"flip", 0.08}}}};
  const json reference = {{"method", "reference"},
                          {"vs_raytraced", {{"mae", 0.013}, {"bias", -0.001}}},
                          {"vs_reference", {{"mae", 0.0}, {"itself", true}}}};
  return {{"schema_version", 1},
          {"runs",
           {aoRun("ldm", 3.0, ldm, {{"ldm_build", {{"median", 1.5}}}, {"ambient_occlusion", {{"median", 0.5}}}}),
            aoRun("reference", 9.0, reference, {{"ambient_occlusion", {{"median", 7.0}}}})}}};
}

TEST(AoTable, ListsTimesMemoryAndErrorsAndThePapersFigures) {
  const std::string md = aoTableMarkdown(results());
  EXPECT_NE(md.find("| ldm | ldm | 512 | 200² | 800x800 | 1.500 | 0.500 | 3.000 | 2.0 (1.9) | 2.12 / 11 / 27 | 0 | "
                    "0.0104 | +0.0060 | 0.0200 | 0.0800 |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| reference | reference | — | — | 800x800 | — | 7.000 | 9.000 | — | — | — | 0.0130 | -0.0010 | "
                    "0 (itself) | — |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("512.4 ms and 805.5 MB"), std::string::npos);
  EXPECT_EQ(aoTableMarkdown(json{{"schema_version", 1}, {"runs", json::array()}}), "");
}

// A sweep whose every run computes AO is judged by its AO error: the reference has error 0 and is
// slower, the LDM run is faster with an error; neither dominates the other.
TEST(AoTable, TheAccuracyReportOfAnAoSweepMeasuresTheAoError) {
  const AccuracyFront f = accuracyFront(results());
  EXPECT_EQ(f.measure, AccuracyMeasure::AoError);
  ASSERT_EQ(f.points.size(), 2u);
  EXPECT_DOUBLE_EQ(f.points[0].error, 0.02);
  EXPECT_DOUBLE_EQ(f.points[1].error, 0.0);
  EXPECT_TRUE(f.points[0].onFront);
  EXPECT_TRUE(f.points[1].onFront);
  EXPECT_NE(accuracyReportMarkdown(results()).find("AO error (MAE vs reference)"), std::string::npos);
}

// AO runs are compared within their d_max only (each against the reference of its own d_max), by
// the AO's own time (ldm_build + ambient_occlusion), not the frame's. Frame times here are chosen
// to contradict: by frame time "b" would dominate "a"; by AO time "a" dominates "b". "c" has the
// largest error and time of all, yet is its own d_max's front.
TEST(AoTable, TheAoFrontIsPerDMaxAndOnTheAoTime) {
  auto ao = [](double dMax, double mae) {
    return json{{"method", "ldm"}, {"d_max", dMax}, {"vs_reference", {{"mae", mae}}}};
  };
  const json r = {
      {"schema_version", 1},
      {"runs",
       {aoRun("a", 10.0, ao(1.0, 0.02), {{"ldm_build", {{"median", 1.0}}}, {"ambient_occlusion", {{"median", 1.0}}}}),
        aoRun("b", 1.0, ao(1.0, 0.03), {{"ambient_occlusion", {{"median", 3.0}}}}),
        aoRun("c", 20.0, ao(2.0, 0.05), {{"ambient_occlusion", {{"median", 5.0}}}})}}};
  const AccuracyFront f = accuracyFront(r);
  ASSERT_EQ(f.points.size(), 3u);
  EXPECT_DOUBLE_EQ(f.points[0].timeMs, 2.0);
  EXPECT_DOUBLE_EQ(f.points[1].timeMs, 3.0);
  EXPECT_EQ(f.points[0].group, "d_max = 1 m");
  EXPECT_EQ(f.points[2].group, "d_max = 2 m");
  EXPECT_EQ(f.groups.size(), 2u);
  EXPECT_TRUE(f.points[0].onFront);
  EXPECT_FALSE(f.points[1].onFront);
  EXPECT_TRUE(f.points[2].onFront);
  const std::string md = accuracyReportMarkdown(r);
  EXPECT_NE(md.find("AO time: ldm_build + ambient_occlusion medians (ms)"), std::string::npos) << md;
  EXPECT_NE(md.find("| 2.000 | 1 | 0.0200 |"), std::string::npos) << md;
  const std::string svg = accuracyReportSvg(r);
  EXPECT_NE(svg.find("[d_max = 2 m] (front)"), std::string::npos) << svg;
  EXPECT_NE(svg.find("fill-opacity=\"0\""), std::string::npos) << svg;  // b, off its front: hollow
}

}  // namespace
}  // namespace hb
