// Each study prints its own tables (all_tables.h): the thesis's Tables 5.1/5.2 only where some run
// is one of their rows, never a frame of another study under their labels; the effect tables for
// those effects; and the per-variant table where no table has rows. Whatever the study, the
// resources each run's frame built on the CPU.
#include "report/all_tables.h"

#include <fstream>

#include <gtest/gtest.h>

#include "report/results_fixture_test_util.h"
#include "report/tables.h"

namespace hb {
namespace {

using nlohmann::json;

json thesisFixture() { return testing::thesisResultsFixture(); }

// The thesis's best configuration (Table 5.2's 8x8 row) with ambient occlusion computed too: the
// layered-depth-maps sweeps' frame.
json aoResults() {
  json results = thesisFixture();
  json run = results["runs"][0];
  run["name"] = "ldm 512 x 256^2";
  run["params"] = {{"tile_size", 8}, {"light_culling", true}, {"aabb", true}, {"normal_culling", "improved"}};
  run["effects"] = {{"shadows", {{"runs", true}}}, {"ambient_occlusion", {{"runs", true}}}};
  run["ambient_occlusion"] = {{"method", "ldm"}, {"directions", 512}, {"ldm_resolution", 256}};
  results["runs"] = json::array({run});
  return results;
}

TEST(AllTables, AThesisSweepPrintsTheThesisTables) {
  const std::string md = allTablesMarkdown(thesisFixture());
  EXPECT_NE(md.find("## Table 5.1"), std::string::npos);
  EXPECT_NE(md.find("## Table 5.2"), std::string::npos);
  EXPECT_EQ(md.find("## Runs"), std::string::npos);
}

TEST(AllTables, AnAoSweepPrintsItsTableAndNoThesisTables) {
  const json results = aoResults();
  const std::string md = allTablesMarkdown(results);
  EXPECT_EQ(md.find("Table 5.1"), std::string::npos) << md;
  EXPECT_EQ(md.find("missing (not in results)"), std::string::npos) << md;
  EXPECT_NE(md.find("## Ambient occlusion"), std::string::npos) << md;
  EXPECT_NE(md.find("# Tables"), std::string::npos) << md;
  // The AO frame never stands in for the 8x8 row, whatever its parameters.
  for (const ThesisRow& r : thesisRows(results)) EXPECT_EQ(r.status, "missing") << r.label;
}

TEST(AllTables, ALightCountOrAntiAliasingStudyIsNotTheThesis) {
  for (const auto& [key, value] : std::vector<std::pair<std::string, json>>{{"light_count", 100}, {"aa", "msaa4"}}) {
    json results = thesisFixture();
    for (json& run : results["runs"]) run["params"][key] = value;
    for (const ThesisRow& r : thesisRows(results)) EXPECT_EQ(r.status, "missing") << key << ": " << r.label;
    json thesis = thesisFixture();
    for (json& run : thesis["runs"]) run["params"]["light_count"] = 10;  // the thesis's own count matches
    EXPECT_EQ(thesisRows(thesis)[0].status, "ok");
  }
}

TEST(AllTables, RunsNoTableHasRowsForGetThePerVariantTable) {
  json results = thesisFixture();
  for (json& run : results["runs"]) run["params"]["depth_slices"] = 32;  // beyond the thesis, no other table
  const std::string md = allTablesMarkdown(results);
  EXPECT_EQ(md.find("Table 5.1"), std::string::npos) << md;
  EXPECT_NE(md.find("## Runs"), std::string::npos) << md;
  // One row per run, with its frame median and its top-level passes.
  size_t rows = 0;
  for (size_t at = md.find("\n| "); at != std::string::npos; at = md.find("\n| ", at + 1)) ++rows;
  EXPECT_EQ(rows, 1 + results["runs"].size()) << md;  // the header and a row per run
  EXPECT_NE(md.find("| baseline_t8 | ok | 4.000 |"), std::string::npos) << md;
  EXPECT_NE(md.find("shadows "), std::string::npos) << md;
}

// Two runs of the fixture: the first's frame built our BVH and the TLAS (and wrote a depth buffer,
// which is not built); the second's frame built nothing.
json builtResults() {
  json results = thesisFixture();
  json built = results["runs"][0], plain = results["runs"][1];
  built["name"] = "ao | rt";  // a '|' the table must escape
  built["frame_resources"] = {
      {"depth", {{"format", "D32_SFLOAT"}, {"size", "800x800"}, {"bytes", 2560000}, {"users", {"shading"}}}},
      {"trace_bvh",
       {{"format", "gpu::PrimaryBvhNode"},
        {"bytes", 8275328},
        {"key", "trace_bvh: binary SAH, collapsed to width 4"},
        {"built_bytes", 20852672},
        {"build_ms", 133.233263},
        {"build_clock", "cpu"},
        {"built_by", "renderer"},
        {"users", {"shadows", "ambient_occlusion", "raybench"}}}},
      {"tlas",
       {{"format", "acceleration structure"},
        {"bytes", 24049408},
        {"built_bytes", 24049408},
        {"build_ms", 7.650216},
        {"build_clock", "cpu"},
        {"built_by", "renderer"}}}};  // no users recorded
  plain["frame_resources"] = {{"depth", {{"format", "D32_SFLOAT"}, {"bytes", 2560000}, {"users", {"shading"}}}}};
  results["runs"] = json::array({built, plain});
  return results;
}

TEST(AllTables, EachBuiltResourceOfEachRunIsARowWithItsBuildAndBytes) {
  const json results = builtResults();
  const std::string table = builtResourcesTableMarkdown(results);
  // The header, then the rows in the order frame_resources lists them: tlas, trace_bvh. MB = 2^20 bytes.
  const std::string rows = table.substr(table.find("| Run |"));
  EXPECT_EQ(rows,
            "| Run | Resource | Built by | Build (ms, CPU wall clock) | MB built | MB read | Users |\n"
            "|---|---|---|---:|---:|---:|---|\n"
            "| ao \\| rt | tlas | renderer | 7.65 | 22.94 | 22.94 | — |\n"
            "| ao \\| rt | trace_bvh | renderer | 133.23 | 19.89 | 7.89 | shadows, ambient_occlusion, raybench |\n")
      << table;
  EXPECT_NE(table.find("CPU wall clock"), std::string::npos) << table;
  const std::string md = allTablesMarkdown(results);
  EXPECT_NE(md.find("## Built once a frame\n\n"), std::string::npos) << md;
  EXPECT_NE(md.find(rows), std::string::npos) << md;
}

TEST(AllTables, AFileWithoutBuiltResourcesHasNoBuiltTable) {
  json results = builtResults();
  results["runs"].erase(0);  // leaves the run whose frame_resources built nothing
  EXPECT_EQ(builtResourcesTableMarkdown(results), "");
  EXPECT_EQ(allTablesMarkdown(results).find("Built once a frame"), std::string::npos);
  EXPECT_EQ(allTablesMarkdown(thesisFixture()).find("Built once a frame"), std::string::npos);  // no frame_resources
}

}  // namespace
}  // namespace hb
