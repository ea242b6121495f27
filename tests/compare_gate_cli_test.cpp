// compare's gate on committed H100 files (results/h100/): the thesis sweep at 02f03e1 against the
// same config at 2b33675, where forward shading became ~8.7 % and light culling ~24 % slower while
// the frame moved 3.6 %, under the 5 % threshold. Gating on frames misses it; --gate all names
// both passes and nothing else, and an A/A pair of 2b33675 (the same machine ten minutes apart)
// passes every gate.
#include <algorithm>
#include <filesystem>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tool_process.h"

namespace {

using namespace hb::testing;

const fs::path kResults = fs::path(HYBRIDBENCH_SOURCE_DIR) / "results/h100";
const std::string k02f03e1 = (kResults / "thesis/results.json.gz").string();
const std::string k2b33675 = (kResults / "thesis-2b33675/results.json.gz").string();
const std::string k2b33675Repeat = (kResults / "thesis-2b33675/results-repeat.json.gz").string();

class CompareGate : public ToolTest {};

TEST_F(CompareGate, FramesAloneMissTheShadingAndCullingRegressionThatAllCatches) {
  const RunResult frame = run({"compare", k02f03e1, k2b33675});
  EXPECT_EQ(frame.exitCode, 0) << frame.out << frame.err;

  const RunResult all = run({"compare", k02f03e1, k2b33675, "--gate", "all", "--json"});
  EXPECT_EQ(all.exitCode, 1) << all.err;
  const json report = json::parse(all.out, nullptr, false);
  ASSERT_TRUE(report.is_object()) << all.out;
  std::set<std::string> gated;
  for (const json& row : report["rows"])
    if (row["gates"].get<bool>()) {
      gated.insert(row["pass"].get<std::string>());
      // Each gating row is significant, beyond the threshold, and its interval holds its ratio.
      EXPECT_LT(row["p"].get<double>(), 0.05) << row.dump();
      EXPECT_GT(row["ratio"].get<double>(), 1.05) << row.dump();
      EXPECT_LE(row["ci_low"].get<double>(), row["ratio"].get<double>()) << row.dump();
      EXPECT_GE(row["ci_high"].get<double>(), row["ratio"].get<double>()) << row.dump();
    }
  EXPECT_EQ(gated, (std::set<std::string>{"light_culling", "shading"})) << all.out;
  EXPECT_FALSE(report["failures"].empty());

  // JUnit: each gating pass is a failure naming its ratio and interval.
  const RunResult junit = run({"compare", k02f03e1, k2b33675, "--gate", "all", "--format", "junit"});
  EXPECT_EQ(junit.exitCode, 1);
  EXPECT_NE(junit.out.find("name=\"shading\""), std::string::npos);
  EXPECT_NE(junit.out.find("<failure type=\"slower\" message=\"slower: B/A 1.08"), std::string::npos) << junit.out;

  // A floor above the passes' medians takes them out of the gate: light culling is ~0.05 ms.
  const RunResult floor = run({"compare", k02f03e1, k2b33675, "--gate", "passes", "--min-ms", "0.1", "--json"});
  const json f = json::parse(floor.out, nullptr, false);
  ASSERT_TRUE(f.is_object()) << floor.out;
  for (const json& row : f["rows"])
    if (row["gates"].get<bool>()) {
      EXPECT_EQ(row["pass"], "shading") << row.dump();
    }
}

TEST_F(CompareGate, AnAaPairPassesEveryGateAndEveryRatioLiesInItsInterval) {
  const RunResult r = run({"compare", k2b33675, k2b33675Repeat, "--gate", "all", "--json"});
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
  const json report = json::parse(r.out, nullptr, false);
  ASSERT_TRUE(report.is_object()) << r.out;
  for (const json& row : report["rows"]) {
    EXPECT_FALSE(row["gates"].get<bool>()) << row.dump();
    EXPECT_LE(row["ci_low"].get<double>(), row["ratio"].get<double>()) << row.dump();
    EXPECT_GE(row["ci_high"].get<double>(), row["ratio"].get<double>()) << row.dump();
  }
}

TEST_F(CompareGate, ABadGateOrFloorIsOneLine) {
  const RunResult g = run({"compare", k2b33675, k2b33675Repeat, "--gate", "some"});
  EXPECT_EQ(g.exitCode, 2);
  EXPECT_NE(g.err.find("--gate"), std::string::npos) << g.err;
  const RunResult m = run({"compare", k2b33675, k2b33675Repeat, "--min-ms", "-1"});
  EXPECT_EQ(m.exitCode, 2);
  EXPECT_NE(m.err.find("--min-ms -1"), std::string::npos) << m.err;
  EXPECT_EQ(std::count(m.err.begin(), m.err.end(), '\n'), 1) << m.err;
}

// The between-run noise (docs/usage.md "Between-run noise"): two sweeps at once on one H200 with the
// driver's pipeline gate rows on within-run noise alone, and none with the committed noise file,
// whose use the output names; `noise` writes a file compare reads; bad input is one line, exit 2.
TEST_F(CompareGate, TheNoiseFileHoldsTheH200PipelinesAaPairAndBadInputIsOneLine) {
  const fs::path h200 = fs::path(HYBRIDBENCH_SOURCE_DIR) / "results/h200/concurrent/thesis-aa";
  const std::string a = (h200 / "0-nvidia-h200/results.json.gz").string();
  const std::string b = (h200 / "1-nvidia-h200/results.json.gz").string();
  const std::string noise = (fs::path(HYBRIDBENCH_SOURCE_DIR) / "results/noise/noise.json").string();
  EXPECT_EQ(run({"compare", a, b, "--gate", "all"}).exitCode, 1);
  const RunResult held = run({"compare", a, b, "--gate", "all", "--noise", noise, "--json"});
  EXPECT_EQ(held.exitCode, 0) << held.err;
  const json report = json::parse(held.out, nullptr, false);
  ASSERT_TRUE(report.is_object()) << held.out;
  EXPECT_EQ(report["noise"].get<std::string>().rfind("between-run (" + noise + ": 12 A/A pairs)", 0), 0u)
      << report["noise"];
  size_t within = 0;
  for (const json& row : report["rows"])
    within += row["held"].get<std::string>().rfind("within the between-run", 0) == 0;
  EXPECT_GT(within, 0u);

  const RunResult written = run({"noise", a, b, "--no-check", "--out", (dir / "n.json").string()});
  EXPECT_EQ(written.exitCode, 0) << written.err;
  EXPECT_EQ(run({"compare", a, b, "--gate", "all", "--noise", (dir / "n.json").string()}).exitCode, 0);

  for (const std::vector<std::string>& bad : {std::vector<std::string>{"noise", a, b, k02f03e1},
                                              {"noise", k02f03e1, b},
                                              {"compare", a, b, "--noise", k02f03e1},
                                              {"compare", a, b, "--noise", (dir / "none.json").string()}}) {
    const RunResult r = run(bad);
    EXPECT_EQ(r.exitCode, 2) << bad[0] << " " << bad.back() << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
}

}  // namespace
