#include "report/primary_table.h"

#include <gtest/gtest.h>

namespace hb {
namespace {

using nlohmann::json;

json run(const char* name, const char* pass, double ms, json primary) {
  return {{"name", name},
          {"status", "ok"},
          {"passes", {{pass, {{"median", ms}}}}},
          {"frame_ms", {{"median", 4.0}}},
          {"primary", primary}};
}

TEST(PrimaryTable, SpeedUpIsThePrepassTimeOverThePassTimeAndOpsFollowFig10) {
  const json results = {
      {"schema_version", 1},
      {"runs",
       {run("hardware", "depth_prepass", 0.9, {{"method", "hardware"}}), run("3dr", "raster3d", 0.45,
                                                                             {{"method", "3dr"},
                                                                              {"triangle_setups", 1000000},
                                                                              {"pixels_tested", 2000000},
                                                                              {"edge_evaluations_per_pixel", 3.0},
                                                                              {"atomics_per_pixel", 1.5},
                                                                              {"fp64_fallback_rate", 0.001}})}}};
  const std::string md = primaryTableMarkdown(results);
  EXPECT_NE(md.find("| 3dr | 3dr | 0.450 | 2.00x | 4.000 | 1000000 | 2000000 | 3.0 | 1.50 | 0.1000 % | 81.0 |"),
            std::string::npos)
      << md;  // 57 x 1e6 + 12 x 2e6 = 81e6
  EXPECT_NE(md.find("| hardware | hardware | 0.900 | 1.00x |"), std::string::npos) << md;
}

TEST(PrimaryTable, RayCastingIsTimedByItsOwnPassAndCoverageIsShownWhereCounted) {
  const json results = {{"schema_version", 1},
                        {"runs",
                         {run("hardware", "depth_prepass", 0.9, {{"method", "hardware"}}),
                          run("raycast", "raycast", 0.3, {{"method", "raycast"}, {"coverage_check", "not counted"}}),
                          run("2dr", "raster3d", 0.6,
                              {{"method", "2dr"},
                               {"coverage_check", {{"double_covers", 14}, {"holes", 12}}},
                               {"against_ray_cast", {{"not_ties", 472}}}})}}};
  const std::string md = primaryTableMarkdown(results);
  EXPECT_NE(md.find("| raycast | raycast | 0.300 | 3.00x |"), std::string::npos) << md;
  EXPECT_NE(md.find("| — | — | — |\n"), std::string::npos) << md;  // raycast: no coverage count, no comparison, no bins
  EXPECT_NE(md.find("| 14 / 12 | 472 | — |\n"), std::string::npos) << md;
}

TEST(PrimaryTable, ANonPerspectiveViewIsNamedAndItsEmptyBinsAreAShare) {
  const json results = {{"schema_version", 1},
                        {"runs",
                         {run("paraboloid, 3dr-binned", "raster3d", 0.5,
                              {{"method", "3dr-binned"},
                               {"projection", "paraboloid"},
                               {"bins_refined", 400},
                               {"bins_refined_without_hit", 100}})}}};
  const std::string md = primaryTableMarkdown(results);
  EXPECT_NE(md.find("| paraboloid, 3dr-binned | 3dr-binned (paraboloid) |"), std::string::npos) << md;
  EXPECT_NE(md.find("| 25.0 % |\n"), std::string::npos) << md;
}

TEST(PrimaryTable, ResultsWithoutPrimaryBlocksGiveNoTable) {
  const json results = {{"schema_version", 1}, {"runs", {{{"name", "a"}, {"status", "ok"}}}}};
  EXPECT_EQ(primaryTableMarkdown(results), "");
}

}  // namespace
}  // namespace hb
