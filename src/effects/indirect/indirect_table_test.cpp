#include "effects/indirect/indirect_table.h"

#include <gtest/gtest.h>

#include "report/accuracy_report.h"

namespace hb {
namespace {

using nlohmann::json;

json indirectRun(const char* name, double frameMs, json ind, json passes) {
  return {{"name", name},
          {"status", "ok"},
          {"params", {{"resolution", {800, 800}}}},
          {"passes", passes},
          {"frame_ms", {{"median", frameMs}}},
          {"indirect", ind}};
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
  EXPECT_NE(md.find("| ldm | ldm | 512 | 200² | 16² | 800x800 | 2.000 | 0.500 | 7.000 | 10.000 | 1000 | 400 | 60.0 % | "
                    "3.0 | 0.0660 | 0.977 | 0.1350 | 0.797 | 0.2700 |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| rt | raytraced | 512 | — | 16² | 800x800 | — | 3.000 | 7.000 | 12.000 | 1000 | 410 | 59.0 % | "
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

}  // namespace
}  // namespace hb
