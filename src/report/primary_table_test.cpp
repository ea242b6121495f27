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
  EXPECT_NE(md.find("| 3dr | 3dr | 0.450 | 2.00x | — | 4.000 | 1000000 | 2000000 | 3.0 | 1.50 | 0.1000 % | 81.0 |"),
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

// A run as the analysis records it: r3d_thread_box in its params, paper_scalar_ops_estimate in "primary".
json rasterRun(const char* name, const char* method, double ms, int threadBox, double paperOps,
               json extra = json::object()) {
  json primary = {{"method", method}, {"paper_scalar_ops_estimate", paperOps}};
  primary.update(extra);
  json r = run(name, "raster3d", ms, primary);
  r["params"] = {{"r3d_thread_box", threadBox}};
  return r;
}

// The row of the run named `name`, from its leading "| name |" to its end of line.
std::string rowOf(const std::string& md, const std::string& name) {
  const size_t start = md.find("\n| " + name + " |");
  if (start == std::string::npos) return "";
  return md.substr(start + 1, md.find('\n', start + 1) - start - 1);
}

TEST(PrimaryTable, TimeAndPaperInstructionsAreRelativeTo2drBruteForceAsInFig9) {
  const json results = {{"schema_version", 1},
                        {"runs",
                         {rasterRun("2dr", "2dr", 2.0, 64, 400e6), rasterRun("3dr", "3dr", 1.0, 64, 100e6),
                          rasterRun("raycast", "raycast", 1.0, 64, 0.0)}}};
  const std::string md = primaryTableMarkdown(results);
  // Columns: Run, Method, Primary, Speed-up vs prepass (no hardware run: —), Time vs 2DR brute force.
  EXPECT_NE(rowOf(md, "3dr").find("| 3dr | 3dr | 1.000 | — | 0.50x |"), std::string::npos) << md;
  EXPECT_NE(rowOf(md, "2dr").find("| 2dr | 2dr | 2.000 | — | 1.00x |"), std::string::npos) << md;
  // Paper ops (M), the record's estimate, then Paper instr. vs 2DR: 100e6 / 400e6.
  EXPECT_NE(rowOf(md, "3dr").find(" | 100.0 | 0.25x | "), std::string::npos) << md;
  EXPECT_NE(rowOf(md, "2dr").find(" | 400.0 | 1.00x | — | — | — |"), std::string::npos) << md;
  EXPECT_NE(rowOf(md, "raycast").find(" | 0.0 | — | "), std::string::npos) << md;  // no estimate, not free
  EXPECT_NE(md.find("| Time vs 2DR brute force |"), std::string::npos) << md;
  EXPECT_NE(md.find("| Paper instr. vs 2DR |"), std::string::npos) << md;
  EXPECT_NE(md.find("ran on a CPU"), std::string::npos) << md;
  EXPECT_EQ(md.find("need a run with primary=2dr"), std::string::npos) << md;
}

TEST(PrimaryTable, TheReference2drRunIsTheOneWithTheSameThreadBoxElseTheFirst) {
  const json results = {
      {"schema_version", 1},
      {"runs",
       {rasterRun("2dr box 64", "2dr", 2.0, 64, 400e6), rasterRun("2dr box 256", "2dr", 4.0, 256, 800e6),
        rasterRun("3dr box 256", "3dr", 1.0, 256, 100e6), rasterRun("3dr box 16", "3dr", 1.0, 16, 100e6)}}};
  const std::string md = primaryTableMarkdown(results);
  EXPECT_NE(rowOf(md, "3dr box 256").find("| 1.000 | — | 0.25x |"), std::string::npos) << md;  // 1 / 4
  EXPECT_NE(rowOf(md, "3dr box 16").find("| 1.000 | — | 0.50x |"), std::string::npos) << md;   // 1 / 2: first
  EXPECT_NE(rowOf(md, "2dr box 256").find("| 4.000 | — | 1.00x |"), std::string::npos) << md;  // itself
}

TEST(PrimaryTable, Without2drRunTheColumnsVs2drAreEmptyAndTheCaptionSaysWhy) {
  const json results = {{"schema_version", 1},
                        {"runs",
                         {rasterRun("3dr", "3dr", 1.0, 64, 100e6),  // 2dr-binned is not the reference
                          rasterRun("2dr-binned", "2dr-binned", 0.5, 64, 50e6)}}};
  const std::string md = primaryTableMarkdown(results);
  EXPECT_NE(rowOf(md, "3dr").find("| 3dr | 3dr | 1.000 | — | — |"), std::string::npos) << md;
  EXPECT_NE(rowOf(md, "2dr-binned").find("| 2dr-binned | 2dr-binned | 0.500 | — | — |"), std::string::npos) << md;
  EXPECT_EQ(md.find("0.50x"), std::string::npos) << md;
  EXPECT_EQ(md.find("2.00x"), std::string::npos) << md;
  EXPECT_NE(md.find("need a run with primary=2dr"), std::string::npos) << md;
}

TEST(PrimaryTable, TheBvhMethodsShowNodesFrustaAndWhatTheyCulled) {
  const json results = {{"schema_version", 1},
                        {"runs",
                         {rasterRun("2dr", "2dr", 2.0, 64, 400e6),
                          rasterRun("3dr-full", "3dr-full", 1.0, 64, 100e6,
                                    {{"bvh_nodes_visited", 123456},
                                     {"frusta", 40},
                                     {"frusta_split", 1234},
                                     {"triangles_culled_frustum", 5000},
                                     {"triangles_culled_occlusion", 7},
                                     {"blocks_culled_early_z", 1000000}}),
                          rasterRun("3dr-binned", "3dr-binned", 1.5, 64, 200e6, {{"blocks_culled_early_z", 250}})}}};
  const std::string md = primaryTableMarkdown(results);
  EXPECT_NE(md.find("| Empty bins | Nodes visited | Frusta (split) | Culled: frustum / occlusion / early-z |\n"),
            std::string::npos)
      << md;
  EXPECT_NE(rowOf(md, "3dr-full").find("| — | 123,456 | 40 (1,234) | 5,000 / 7 / 1,000,000 |"), std::string::npos)
      << md;
  // 2dr is not a BVH method: Paper instr. vs 2DR, then six empty cells, the last three the BVH ones.
  EXPECT_NE(rowOf(md, "2dr").find("| 1.00x | — | — | — | — | — | — |"), std::string::npos) << md;
  // A binned method records its early-z blocks alone.
  EXPECT_NE(rowOf(md, "3dr-binned").find("| — | — | — / — / 250 |"), std::string::npos) << md;
  EXPECT_NE(md.find("Nodes visited:"), std::string::npos) << md;  // defined in the caption
}

TEST(PrimaryTable, WithoutBvhCountersTheirColumnsAreLeftOut) {
  const json results = {{"schema_version", 1},
                        {"runs", {rasterRun("2dr", "2dr", 2.0, 64, 400e6), rasterRun("3dr", "3dr", 1.0, 64, 100e6)}}};
  const std::string md = primaryTableMarkdown(results);
  EXPECT_EQ(md.find("Nodes visited"), std::string::npos) << md;
  EXPECT_EQ(md.find("Frusta (split)"), std::string::npos) << md;
  EXPECT_EQ(md.find("Culled:"), std::string::npos) << md;
  EXPECT_NE(md.find("| Empty bins |\n|"), std::string::npos) << md;
}

TEST(PrimaryTable, ResultsWithoutPrimaryBlocksGiveNoTable) {
  const json results = {{"schema_version", 1}, {"runs", {{{"name", "a"}, {"status", "ok"}}}}};
  EXPECT_EQ(primaryTableMarkdown(results), "");
}

}  // namespace
}  // namespace hb
