// An interrupted `hybridbench sweep` end to end: a sweep stopped by SIGINT or SIGTERM (exit 130) keeps
// exactly its finished runs and --resume completes it without running them again; --resume without
// --out, or into results it cannot continue, is refused and keeps them. The built tool runs as a
// child process with HYBRIDBENCH_VALIDATION=1 on the tiny config tests/fixtures/sweep-tiny.json.
#include <signal.h>
#include <sys/wait.h>

#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "sweep_cli.h"

namespace hb::sweep_test {
namespace {

// Kill (SIGINT) after the first finished variant, resume and kill again (SIGTERM) after the next
// one, then resume to the end: finished runs are never lost, changed or run twice.
TEST_F(Sweep, InterruptedSweepKeepsFinishedRunsAndResumeCompletesIt) {
  json variants = readJson(kSweepFixture)["variants"];
  variants.push_back({{"name", "light culling only"}, {"params", {{"normal_culling", "off"}}}});
  variants.push_back({{"name", "32x32"}, {"params", {{"tile_size", 32}}}});
  const fs::path config = configWith("sweep-kill", variants);
  const fs::path out = dir / "out";
  // 30 measured frames: ~2 s per variant on lavapipe, so a signal lands well before the end.
  const std::vector<std::string> args{"sweep", config.string(), "--out", out.string(), "--no-images", "--frames", "30"};
  std::vector<std::string> resumeArgs = args;
  resumeArgs.push_back("--resume");

  auto expectConsistent = [&](const json& results) {
    for (const json& run : results["runs"]) {
      const auto it =
          std::find_if(variants.begin(), variants.end(), [&](const json& v) { return v["name"] == run["name"]; });
      ASSERT_NE(it, variants.end()) << run["name"];
      ASSERT_EQ(run.value("status", ""), "ok") << run.dump();
      expectTimingBlock(run["frame_ms"], 30, run["name"].get<std::string>());
    }
    expectCsvMatches(readFile(out / "results.csv"), results);
    EXPECT_NE(readFile(out / "tables.md").find("Table 5.1"), std::string::npos);
  };

  const pid_t first = start(args);
  ASSERT_TRUE(waitForRuns(first, out, 1));
  kill(first, SIGINT);
  const RunResult r1 = wait(first);
  EXPECT_EQ(r1.exitCode, 130) << r1.out << r1.err;
  EXPECT_EQ(hb::testing::processesMentioning(out.string()), std::vector<std::string>{});  // the worker ended too
  EXPECT_NE(r1.out.find("--resume --out " + out.string()), std::string::npos) << r1.out;
  const json afterInt = readJson(out / "results.json");
  ASSERT_FALSE(afterInt.is_discarded());
  const size_t k1 = afterInt["runs"].size();
  ASSERT_GE(k1, 1u);
  ASSERT_LT(k1, variants.size()) << "the sweep finished before the signal: make its variants longer";
  expectConsistent(afterInt);

  const pid_t second = start(resumeArgs);
  ASSERT_TRUE(waitForRuns(second, out, k1 + 1));
  kill(second, SIGTERM);
  const RunResult r2 = wait(second);
  EXPECT_EQ(r2.exitCode, 130) << r2.out << r2.err;
  EXPECT_EQ(hb::testing::processesMentioning(out.string()), std::vector<std::string>{});
  EXPECT_NE(r2.out.find("resume: " + std::to_string(k1) + " of " + std::to_string(variants.size())), std::string::npos)
      << r2.out;
  const json afterTerm = readJson(out / "results.json");
  ASSERT_FALSE(afterTerm.is_discarded());
  const size_t k2 = afterTerm["runs"].size();
  ASSERT_GT(k2, k1);
  ASSERT_LT(k2, variants.size()) << "the resumed sweep finished before the signal";
  expectConsistent(afterTerm);

  const RunResult r3 = run(resumeArgs);
  ASSERT_EQ(r3.exitCode, 0) << r3.out << r3.err;
  EXPECT_NE(r3.out.find("resume: " + std::to_string(k2) + " of "), std::string::npos) << r3.out;
  const json final_ = readJson(out / "results.json");
  ASSERT_FALSE(final_.is_discarded());
  EXPECT_EQ(runNames(final_), variantNames(json{{"variants", variants}}));  // each once, in config order
  expectConsistent(final_);
  for (size_t i = 0; i < final_["runs"].size(); ++i)
    expectCompleteRun(final_["runs"][i], final_["context"]["config"]["variants"][i], 30);
  // Runs finished before a signal are carried over verbatim, samples included.
  for (size_t i = 0; i < k1; ++i) EXPECT_EQ(final_["runs"][i], afterInt["runs"][i]) << i;
  for (size_t i = 0; i < k2; ++i) EXPECT_EQ(final_["runs"][i], afterTerm["runs"][i]) << i;
}

TEST_F(Sweep, ResumeWithoutOutIsOneLineNamingTheFlag) {
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"sweep", "--resume"}, {"sweep", kSweepFixture.string(), "--resume"}}) {
    const RunResult r = run(args);
    EXPECT_EQ(r.exitCode, 2) << r.out << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find("--out"), std::string::npos) << r.err;
  }
}

// --resume into results of another config, or into a file that is not JSON, is refused (one
// line naming the file, exit 2) and leaves the file as it was.
TEST_F(Sweep, ResumeRefusesResultsItCannotContinueAndKeepsThem) {
  const fs::path out = dir / "out";
  fs::create_directories(out);
  const fs::path results = out / "results.json";
  const std::string foreign =
      json{{"schema_version", 1}, {"context", {{"config", {{"name", "another"}}}}}, {"runs", json::array()}}.dump(1);
  for (const std::string& text : {foreign, std::string("{\"schema_version\": 1, \"runs\": [")}) {
    writeFile(results, text);
    const RunResult r = run({"sweep", kSweepFixture.string(), "--out", out.string(), "--no-images", "--resume"});
    EXPECT_EQ(r.exitCode, 2) << r.out << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find(results.string()), std::string::npos) << r.err;
    EXPECT_EQ(readFile(results), text);
  }
}

}  // namespace
}  // namespace hb::sweep_test
