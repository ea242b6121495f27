// The 3D rasterization paper's Fig. 9 table ("Primary visibility (3D rasterization continuum)" in a
// sweep's tables.md, report/primary_table.cpp) regenerated from a real run on the device present
// (lavapipe in CI): configs/3d-rasterization-ci.json, one variant per primary method of the
// continuum at 160x90, swept through the built hybridbench with HYBRIDBENCH_VALIDATION=1. What is
// held is what a run counts: the table's shape and its 2DR reference, each method's wrong ids
// against the double-precision ray cast, the coverage check, the BVH methods' work and the paper's
// instruction estimates. No time is asserted: 3 frames on a CPU device measure nothing. The table
// is printed so the CI log shows it. 20 to 30 s on lavapipe (2 cores).
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tool_process.h"

namespace {

using namespace hb::testing;

const fs::path kContinuumCiConfig = fs::path(HYBRIDBENCH_SOURCE_DIR) / "configs/3d-rasterization-ci.json";

// The cells of one Markdown table row, trimmed ("| a | b |" -> {"a", "b"}). The run names of the CI
// config hold no '|', so no escaped pipe needs undoing.
std::vector<std::string> continuumRowCells(const std::string& row) {
  std::vector<std::string> cells;
  std::istringstream in(row);
  std::string cell;
  std::getline(in, cell, '|');  // before the first '|'
  while (std::getline(in, cell, '|')) {
    const size_t b = cell.find_first_not_of(' '), e = cell.find_last_not_of(' ');
    cells.push_back(b == std::string::npos ? "" : cell.substr(b, e - b + 1));
  }
  if (!cells.empty() && cells.back().empty()) cells.pop_back();  // after the last '|'
  return cells;
}

// A count of results.json as an integer; fails (and gives -1) when it is not one.
int64_t continuumCount(const json& primary, const json::json_pointer& at) {
  const json& v = primary.contains(at) ? primary.at(at) : json();
  EXPECT_TRUE(v.is_number()) << at.to_string() << " is " << v.dump() << ", not a count";
  return v.is_number() ? v.get<int64_t>() : -1;
}

class ContinuumSweep : public ToolTest {};

TEST_F(ContinuumSweep, RegeneratesFig9OnTheDevicePresent) {
  const json config = readJson(kContinuumCiConfig);
  ASSERT_TRUE(config.is_object() && config.contains("variants")) << kContinuumCiConfig;
  const fs::path out = dir / "sweep";
  const RunResult r = run({"sweep", kContinuumCiConfig.string(), "--out", out.string(), "--no-images"});
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;

  // The table: Fig. 9's columns, one row per variant of the config in its order; printed for the log.
  const std::vector<std::string> table =
      markdownTableRows(readFile(out / "tables.md"), "## Primary visibility (3D rasterization continuum)");
  std::cout << "Primary visibility (3D rasterization continuum) on this device:\n";
  for (const std::string& line : table) std::cout << line << "\n";
  ASSERT_GE(table.size(), 2u) << "tables.md holds no continuum table";
  const std::vector<std::string> header = continuumRowCells(table[0]);
  std::map<std::string, size_t> column;
  for (size_t i = 0; i < header.size(); ++i) column[header[i]] = i;
  for (const char* h : {"Run", "Method", "Time vs 2DR brute force", "Paper instr. vs 2DR"})
    ASSERT_TRUE(column.count(h)) << "no column \"" << h << "\": " << table[0];
  const std::vector<std::string> rows(table.begin() + 2, table.end());
  ASSERT_EQ(rows.size(), config["variants"].size()) << "one row per variant of " << kContinuumCiConfig;
  size_t referenceRows = 0;
  for (size_t i = 0; i < rows.size(); ++i) {
    const std::vector<std::string> cells = continuumRowCells(rows[i]);
    ASSERT_EQ(cells.size(), header.size()) << rows[i];
    EXPECT_EQ(cells[column["Run"]], config["variants"][i]["name"].get<std::string>());
    // 2DR brute force is the reference of both relative columns: 1.00x against itself.
    if (cells[column["Method"]] == "2dr") {
      ++referenceRows;
      EXPECT_EQ(cells[column["Time vs 2DR brute force"]], "1.00x") << rows[i];
      EXPECT_EQ(cells[column["Paper instr. vs 2DR"]], "1.00x") << rows[i];
    }
  }
  EXPECT_EQ(referenceRows, 1u) << "one 2DR brute force row, the reference";

  // The counts, from results.json: each run's primary record by its method (one run per method).
  const json results = readJson(out / "results.json");
  ASSERT_TRUE(results.is_object() && results.contains("runs")) << out / "results.json";
  std::map<std::string, json> byMethod;
  for (const json& run : results["runs"]) {
    ASSERT_TRUE(run.contains("primary")) << run.value("name", "?") << ": " << run.value("error", json()).dump();
    const std::string method = run["primary"].value("method", "?");
    EXPECT_FALSE(byMethod.count(method)) << "two runs of " << method;
    byMethod[method] = run["primary"];
  }
  const std::vector<std::string> methods = {
      "hardware",          "2dr",     "3dr", "3dr-binned", "2dr-binned", "raycast", "3dr-frustum-cull",
      "3dr-frustum-split", "3dr-full"};
  for (const std::string& m : methods) ASSERT_TRUE(byMethod.count(m)) << "no run of " << m;
  using P = json::json_pointer;

  // Visibility against the double-precision ray cast: 3DR (every variant) and the ray cast differ
  // only at ties. 2DR is the paper's float baseline: its 2D homogeneous edge functions lose digits
  // on thin, far triangles and give some pixels to a neighbour (116 of 13,902 here, 0.8 %); held
  // to 2 % of the pixels both hit, so a broken 2DR still shows.
  for (const char* m : {"3dr", "3dr-binned", "3dr-frustum-cull", "3dr-frustum-split", "3dr-full", "raycast"})
    EXPECT_EQ(continuumCount(byMethod[m], P("/against_ray_cast/not_ties")), 0) << m;
  for (const char* m : {"2dr", "2dr-binned"}) {
    const int64_t wrong = continuumCount(byMethod[m], P("/against_ray_cast/not_ties"));
    const int64_t bothHit = continuumCount(byMethod[m], P("/against_ray_cast/both_hit"));
    EXPECT_GT(bothHit, 0) << m;
    EXPECT_LE(50 * wrong, bothHit) << m << ": " << wrong << " wrong ids of " << bothHit << " pixels (more than 2 %)";
  }

  // Coverage against the exact CPU rasterization: 3DR never covers a pixel twice; frustum culling
  // removes only pairs that cover nothing, so 3dr-frustum-cull has no hole either. Occlusion culling
  // skips hidden triangles, so split and full report holes as not counted (a string).
  for (const char* m : {"3dr", "3dr-binned", "3dr-frustum-cull", "3dr-frustum-split", "3dr-full"})
    EXPECT_EQ(continuumCount(byMethod[m], P("/coverage_check/double_covers")), 0) << m;
  for (const char* m : {"3dr", "3dr-binned", "3dr-frustum-cull"})
    EXPECT_EQ(continuumCount(byMethod[m], P("/coverage_check/holes")), 0) << m;
  for (const char* m : {"3dr-frustum-split", "3dr-full"})
    EXPECT_TRUE(byMethod[m].at(P("/coverage_check/holes")).is_string())
        << m << ": holes " << byMethod[m].at(P("/coverage_check/holes")).dump();

  // The BVH methods' work: 32 px frusta over 160x90 are ceil(160/32) x ceil(90/32) = 5 x 3 = 15;
  // split and full split some of them (down to 8 px) and cull some triangles behind the depth.
  const int64_t frusta = (160 + 31) / 32 * ((90 + 31) / 32);
  for (const char* m : {"3dr-frustum-cull", "3dr-frustum-split", "3dr-full"}) {
    EXPECT_GT(continuumCount(byMethod[m], P("/bvh_nodes_visited")), 0) << m;
    EXPECT_EQ(continuumCount(byMethod[m], P("/frusta")), frusta) << m;
  }
  for (const char* m : {"3dr-frustum-split", "3dr-full"}) {
    EXPECT_GT(continuumCount(byMethod[m], P("/frusta_split")), 0) << m;
    EXPECT_GT(continuumCount(byMethod[m], P("/triangles_culled_occlusion")), 0) << m;
  }

  // The paper's instruction estimate (Fig. 10's costs): binning tests fewer pixels than brute force,
  // and 3DR's 57 + 12 per setup and pixel are below 2DR's 73 + 14, so 3dr-binned is below 2dr.
  const json& ops3drBinned = byMethod["3dr-binned"]["paper_scalar_ops_estimate"];
  const json& ops2dr = byMethod["2dr"]["paper_scalar_ops_estimate"];
  ASSERT_TRUE(ops3drBinned.is_number() && ops2dr.is_number()) << ops3drBinned << " " << ops2dr;
  EXPECT_LT(ops3drBinned.get<double>(), ops2dr.get<double>());
}

}  // namespace
