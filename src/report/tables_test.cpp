#include "report/tables.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "base/errors.h"
#include "report/results_fixture_test_util.h"

namespace hb {
namespace {

using nlohmann::json;

// The thesis sweep (testing::thesisResultsFixture says its runs and frame medians).
json fixture() { return testing::thesisResultsFixture(); }

void eraseRun(json& results, const std::string& name) {
  json& runs = results["runs"];
  for (size_t i = 0; i < runs.size(); ++i)
    if (runs[i]["name"] == name) {
      runs.erase(i);
      return;
    }
  FAIL() << "no run " << name;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

TEST(ThesisTables, MarkdownRowsFollowTheThesisOrderWithDiffsToNoOptimisations) {
  const std::string md = thesisTablesMarkdown(fixture());
  // Diff = 100 (t - 4.000) / 4.000, by hand:
  //   2.880 -> -28.00; 2.732 -> -31.70; 2.400 -> -40.00; 2.420 -> -39.50; 3.380 -> -15.50.
  // Thesis columns are the thesis's Tables 5.1 and 5.2 verbatim.
  const std::vector<std::string> expected = {
      "| no optimisations | 4.000 | 0.00 | 16 | 0.00 |",
      "| light culling | 2.880 | -28.00 | 11.52 | -28.00 |",
      "| light culling + AABB | 2.732 | -31.70 | 10.93 | -31.69 |",
      "| light culling + AABB + shadow ray culling | 2.400 | -40.00 | 9.59 | -40.06 |",
      "| light culling + AABB + improved shadow ray culling | 2.420 | -39.50 | 9.67 | -39.56 |",
      "| improved shadow ray culling | 3.380 | -15.50 | 13.55 | -15.31 |",
      // Table 5.2, diff vs 8x8 = 100 (t - 2.420) / 2.420: 2.450 -> 1.2397 -> 1.24;
      // 2.560 -> 5.7851 -> 5.79.
      "| 8x8 | 2.420 | 0.00 | 9.44 |",
      "| 16x16 | 2.450 | 1.24 | 9.56 |",
      "| 32x32 | 2.560 | 5.79 | 9.99 |",
  };
  size_t last = 0;
  for (const std::string& row : expected) {
    const size_t pos = md.find("\n" + row, last);
    ASSERT_NE(pos, std::string::npos) << "row not found after the previous one: " << row << "\n" << md;
    last = pos + 1;
  }
  EXPECT_LT(md.find("## Table 5.1"), md.find("## Table 5.2"));
  EXPECT_EQ(md.find("missing"), std::string::npos);
}

TEST(ThesisTables, ExtraColumnsCarryRaysShadowShareAndMemory) {
  const std::string md = thesisTablesMarkdown(fixture());
  // baseline_t8: traced 20736000, efficiency 0.2, shadows 3.640 / frame 4.000 = 91.0 %, no
  // culling data (0 B). lc_aabb_t8: 1555200 B / 2^20 = 1.4832 MiB -> "1.48 MiB".
  EXPECT_NE(md.find("| no optimisations | 4.000 | 0.00 | 16 | 0.00 | 20736000 | 0.200 | 91.0 % | "
                    "0 B |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| light culling + AABB | 2.732 | -31.70 | 10.93 | -31.69 | 6635520 | 0.625 |"), std::string::npos);
  EXPECT_NE(md.find("| 1.48 MiB |"), std::string::npos);
  // 16x16: 8160 tiles * (8 + 40) B = 391680 B = 382.5 KiB.
  EXPECT_NE(md.find("| 16x16 | 2.450 | 1.24 | 9.56 | 4561920 | 0.909 |"), std::string::npos);
  EXPECT_NE(md.find("| 382.5 KiB |"), std::string::npos);
}

TEST(ThesisTables, HeaderNamesDeviceDriverResolutionSceneAndRevision) {
  const std::string header = lines(thesisTablesMarkdown(fixture())).at(2);
  for (const char* part :
       {"NVIDIA H100 80GB HBM3", "driver 580.159", "1920x1080", "atrium", "9f2b6c1e4a7d", "git 3f2c9a1b7d4e"})
    EXPECT_NE(header.find(part), std::string::npos) << part << " not in: " << header;
}

TEST(ThesisTables, RemovedVariantIsMissingNeverInvented) {
  json results = fixture();
  eraseRun(results, "lc_aabb_t8");
  const std::string md = thesisTablesMarkdown(results);
  EXPECT_NE(md.find("| light culling + AABB | missing (not in results) |  | 10.93 | -31.69 |"), std::string::npos)
      << md;
  // The rows around it are unchanged.
  EXPECT_NE(md.find("| light culling | 2.880 | -28.00 |"), std::string::npos);
  EXPECT_NE(md.find("| light culling + AABB + shadow ray culling | 2.400 | -40.00 |"), std::string::npos);
}

TEST(ThesisTables, MissingBaselineLeavesDiffsUnavailable) {
  json results = fixture();
  eraseRun(results, "baseline_t8");
  const std::string md = thesisTablesMarkdown(results);
  EXPECT_NE(md.find("| no optimisations | missing (not in results) |"), std::string::npos);
  EXPECT_NE(md.find("| light culling | 2.880 | n/a | 11.52 | -28.00 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| 16x16 | 2.450 | 1.24 |"), std::string::npos);  // 5.2 has its own baseline
}

TEST(ThesisTables, RunsAreMatchedByParamsNotByName) {
  json results = fixture();
  for (json& run : results["runs"]) run["name"] = "run_" + run["name"].get<std::string>() + "_x";
  json swapped = fixture();
  std::swap(swapped["runs"][1]["name"], swapped["runs"][2]["name"]);  // names now lie
  const std::string md = thesisTablesMarkdown(swapped);
  EXPECT_EQ(thesisTablesMarkdown(results), thesisTablesMarkdown(fixture()));
  EXPECT_NE(md.find("| light culling | 2.880 | -28.00 |"), std::string::npos);
}

TEST(ThesisTables, RunsWithOptionsBeyondTheThesisNeverStandInForItsRows) {
  struct Option {
    std::string key;
    json beyond, thesis;  // a value beyond the thesis, and the thesis's own
  };
  for (const Option& o :
       std::vector<Option>{{"range_test", true, false}, {"depth_slices", 32, 0}, {"t_min", "scaled", "constant"}}) {
    for (const bool isBeyond : {true, false}) {
      json results = fixture();
      for (json& run : results["runs"])
        if (run["name"] == "lc_t8") run["params"][o.key] = isBeyond ? o.beyond : o.thesis;
      const ThesisRow row = thesisRows(results)[1];  // "light culling"
      if (isBeyond)
        EXPECT_EQ(row.status, "missing") << o.key;
      else
        EXPECT_EQ(row.runName, "lc_t8") << o.key;
    }
  }
}

TEST(ThesisTables, FailedRunIsShownAsFailedWithItsError) {
  json results = fixture();
  for (json& run : results["runs"])
    if (run["name"] == "lc_t8") {
      run["status"] = "error";
      run["error"] = "device lost | in shadows";
    }
  const std::vector<ThesisRow> rows = thesisRows(results);
  EXPECT_EQ(rows[1].status, "error");
  EXPECT_TRUE(std::isnan(rows[1].frameMs));
  const std::string md = thesisTablesMarkdown(results);
  EXPECT_NE(md.find("| light culling | failed (run 'lc_t8') |"), std::string::npos) << md;
  EXPECT_NE(md.find("device lost \\| in shadows"), std::string::npos);  // escaped for Markdown
}

TEST(ThesisTables, PrefersTheSuccessfulRunWhenSeveralMatch) {
  json results = fixture();
  json failed = results["runs"][1];  // baseline_t8
  failed["name"] = "baseline_retry";
  failed["status"] = "error";
  results["runs"].insert(results["runs"].begin(), failed);
  const std::vector<ThesisRow> rows = thesisRows(results);
  EXPECT_EQ(rows[0].runName, "baseline_t8");
  EXPECT_EQ(rows[0].status, "ok");
  EXPECT_NE(rows[0].note.find("2 runs match"), std::string::npos);
}

// Table 5.1's "light culling + AABB + improved shadow ray culling" and Table 5.2's "8x8" have the
// same parameters; a config that runs them apart (configs/thesis.json) names them after their rows,
// and each table shows its own run. Before, both rows showed the first match.
TEST(ThesisTables, EachTableTakesTheRunNamedAfterItsRow) {
  json results = fixture();
  json own51 = results["runs"][5], own52 = results["runs"][5];  // lc_aabb_improved_t8
  own51["name"] = "light culling + AABB + improved shadow ray culling";
  own52["name"] = "8x8";
  own52["frame_ms"]["median"] = 2.5;
  results["runs"].push_back(own51);
  results["runs"].push_back(own52);
  const std::vector<ThesisRow> rows = thesisRows(results);
  EXPECT_EQ(rows[4].runName, "light culling + AABB + improved shadow ray culling");
  EXPECT_EQ(rows[6].label, "8x8");
  EXPECT_EQ(rows[6].runName, "8x8");
  EXPECT_EQ(rows[6].frameMs, 2.5);
  EXPECT_NE(rows[6].note.find("3 runs match; showing '8x8'"), std::string::npos) << rows[6].note;
}

TEST(ThesisTables, CsvHasAHeaderAndOneRowPerTableRow) {
  const std::vector<std::string> csv = lines(thesisTablesCsv(fixture()));
  ASSERT_EQ(csv.size(), 1u + 9u);  // 6 rows of Table 5.1 + 3 of Table 5.2
  EXPECT_EQ(csv[0].rfind("table,configuration,tile_size,light_culling,aabb,normal_culling,status,"
                         "run,frame_ms_median,diff_pct,thesis_frame_ms,thesis_diff_pct",
                         0),
            0u);
  const auto columns = [](const std::string& line) {
    return std::count(line.begin(), line.end(), ',') + 1;  // no quoted commas in the fixture
  };
  for (const std::string& line : csv) EXPECT_EQ(columns(line), columns(csv[0])) << line;
  EXPECT_EQ(csv[1].rfind("5.1,no optimisations,8,false,false,off,ok,baseline_t8,4,0.00,16,0.00,", 0), 0u) << csv[1];
  EXPECT_EQ(csv[2].rfind("5.1,light culling,8,true,false,off,ok,lc_t8,2.88,-28.00,11.52,-28.00,", 0), 0u) << csv[2];
  EXPECT_EQ(csv[8].rfind("5.2,16x16,16,true,true,improved,ok,lc_aabb_improved_t16,2.45,1.24,9.56,,", 0), 0u) << csv[8];
}

TEST(ThesisTables, CsvQuotesFieldsWithCommasAndQuotes) {
  json results = fixture();
  eraseRun(results, "lc_t8");
  results["runs"][1]["name"] = "baseline \"8x8\", v1";  // was baseline_t8
  const std::string csv = thesisTablesCsv(results);
  EXPECT_NE(csv.find("5.1,light culling,8,true,false,off,missing,,,,11.52,-28.00,"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",ok,\"baseline \"\"8x8\"\", v1\",4,0.00,"), std::string::npos) << csv;
}

TEST(ThesisTables, NotAResultsFileIsInputError) {
  EXPECT_THROW(thesisTablesMarkdown(json{{"runs", json::array()}}), InputError);
  EXPECT_THROW(thesisTablesCsv(json::array()), InputError);
}

}  // namespace
}  // namespace hb
