#include "effects/indirect/indirect_table.h"

#include <gtest/gtest.h>

#include "report/accuracy_report.h"
#include "report/results_fixture_test_util.h"

namespace hb {
namespace {

using nlohmann::json;

json indirectRun(const char* name, double frameMs, json ind, json passes) {
  return testing::effectRun(name, frameMs, "indirect", std::move(ind), std::move(passes));
}

json indirectResults() {
  const json ldm = {{"method", "ldm"},
                    {"directions", 512},
                    {"ldm_resolution", 200},
                    {"photons", 16},
                    {"memory_bytes", {{"total", 3.0 * 1048576}}},
                    {"split_photons", {{"slots", 1000}, {"stored", 400}, {"discarded_share", 0.6}}},
                    {"vs_raytraced", {{"rel_mse", 0.066}, {"total_ratio", 0.977}}},
                    {"vs_reference", {{"rel_mse", 0.135}, {"total_ratio", 0.797}, {"flip", 0.27}}}};
  const json rt = {{"method", "raytraced"},
                   {"directions", 512},
                   {"photons", 16},
                   {"memory_bytes", {{"total", 1.0 * 1048576}}},
                   {"split_photons", {{"slots", 1000}, {"stored", 410}, {"discarded_share", 0.59}}},
                   {"vs_raytraced", {{"rel_mse", 0.0}, {"itself", true}}},
                   {"vs_reference", {{"rel_mse", 0.121}, {"total_ratio", 0.816}, {"flip", 0.25}}}};
  return {{"schema_version", 1},
          {"runs",
           {indirectRun("ldm", 10.0, ldm,
                        {{"indirect_ldm_build", {{"median", 2.0}}},
                         {"photon_trace", {{"median", 0.5}}},
                         {"photon_splat", {{"median", 7.0}}}}),
            indirectRun("rt", 12.0, rt, {{"photon_trace", {{"median", 3.0}}}, {"photon_splat", {{"median", 7.0}}}})}}};
}

TEST(IndirectTable, ListsPassTimesPhotonsAndErrorsAndThePapersPhotonTracing) {
  const std::string md = indirectTableMarkdown(indirectResults());
  // K: results written before bounces existed carry none, which is one bounce.
  EXPECT_NE(
      md.find("| ldm | ldm | 1 | 512 | 200² | 16² | 800x800 | 2.000 | 0.500 | 7.000 | 10.000 | 1000 | 400 | 60.0 % | "
              "3.0 | 0.0660 | 0.977 | 0.1350 | 0.797 | 0.2700 |"),
      std::string::npos)
      << md;
  EXPECT_NE(
      md.find("| rt | raytraced | 1 | 512 | — | 16² | 800x800 | — | 3.000 | 7.000 | 12.000 | 1000 | 410 | 59.0 % | "
              "1.0 | 0 (itself) | — | 0.1210 | 0.816 | 0.2500 |"),
      std::string::npos)
      << md;
  EXPECT_NE(md.find("2062 ms"), std::string::npos);
  EXPECT_EQ(indirectTableMarkdown(json{{"schema_version", 1}, {"runs", json::array()}}), "");
}

// A sweep whose every run carries the indirect light's reference error is judged by it.
TEST(IndirectTable, TheAccuracyReportOfAnIndirectSweepMeasuresTheRelativeMse) {
  const AccuracyFront f = accuracyFront(indirectResults());
  EXPECT_EQ(f.measure, AccuracyMeasure::IndirectError);
  ASSERT_EQ(f.points.size(), 2u);
  EXPECT_DOUBLE_EQ(f.points[0].error, 0.135);
  EXPECT_DOUBLE_EQ(f.points[1].error, 0.121);
  EXPECT_TRUE(f.points[0].onFront);  // faster
  EXPECT_TRUE(f.points[1].onFront);  // more accurate
  EXPECT_NE(accuracyReportMarkdown(indirectResults()).find("Indirect error (relMSE vs reference)"), std::string::npos);
}

// The Cornell box calls for AO too, so every run of a bounce sweep carries the same AO error: the
// report judges the runs by what they vary, the indirect light's error, with a front per bounce
// count (each run against the reference of its own K).
std::string md(const json& results) { return accuracyReportMarkdown(results); }

TEST(IndirectTable, ABounceSweepIsJudgedByTheIndirectErrorWithAFrontPerBounceCount) {
  json results = indirectResults();
  json third = results["runs"][0];
  third["name"] = "ldm K=2";
  third["indirect"]["bounces"] = 2;
  third["indirect"]["vs_reference"]["rel_mse"] = 0.2;  // slower and worse than "ldm", but its own K
  third["frame_ms"]["median"] = 30.0;
  results["runs"].push_back(third);
  for (json& run : results["runs"]) run["ambient_occlusion"] = {{"vs_reference", {{"mae", 0.03}}}};
  const AccuracyFront f = accuracyFront(results);
  EXPECT_EQ(f.measure, AccuracyMeasure::IndirectError);
  ASSERT_EQ(f.points.size(), 3u);
  EXPECT_EQ(f.points[0].group, "bounces = 1");
  EXPECT_EQ(f.points[2].group, "bounces = 2");
  EXPECT_TRUE(f.points[2].onFront);  // alone in its group
  EXPECT_NE(md(results).find("of the same bounce count"), std::string::npos);
  // The same AO error everywhere and nothing else: the AO error is still the measure.
  json aoOnly = results;
  for (json& run : aoOnly["runs"]) run.erase("indirect");
  EXPECT_EQ(accuracyFront(aoOnly).measure, AccuracyMeasure::AoError);
}

}  // namespace
}  // namespace hb
