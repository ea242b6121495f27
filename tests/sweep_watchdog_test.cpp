// The sweep's watchdog end to end (app/sweep_worker.h): the tool on lavapipe with the test-only
// switches HYBRIDBENCH_TEST_HANG_VARIANT (the variant stops making progress and ignores SIGTERM,
// as a driver hang does) and HYBRIDBENCH_TEST_CRASH_VARIANT (its process aborts). The sweep must
// record the first as "timeout" and the second as "crashed", finish every other variant in a fresh
// process with the counts an undisturbed sweep gives, exit 3, and leave no process behind.
#include <algorithm>
#include <cstdlib>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include "tool_process.h"

namespace {

using namespace hb::testing;

class SweepWatchdog : public ToolTest {
 protected:
  void TearDown() override {
    ::unsetenv("HYBRIDBENCH_TEST_HANG_VARIANT");
    ::unsetenv("HYBRIDBENCH_TEST_CRASH_VARIANT");
    ToolTest::TearDown();
  }
};

// What a variant computed, without its times: these must not depend on the process it ran in.
json countsOf(const json& run) {
  json c;
  for (const char* key : {"rays", "culling", "accuracy", "memory_bytes", "scene", "params"})
    if (run.contains(key)) c[key] = run[key];
  return c;
}

TEST_F(SweepWatchdog, AHungAndACrashedVariantAreRecordedAndEveryOtherFinishes) {
  const json variants = readJson(kSweepFixture)["variants"];
  ASSERT_GE(variants.size(), 4u) << "the fixture needs a variant before, between and after the two";
  const std::string hang = variants[1]["name"], crash = variants[2]["name"];
  // The longest variant of this fixture takes about 3 s on lavapipe with validation, so 8 s only
  // ends the one that hangs.
  constexpr double kTimeoutS = 8.0, kGraceS = 10.0;  // kGraceS: kWorkerGraceS (app/sweep.h)
  const fs::path out = dir / "out", undisturbed = dir / "undisturbed";
  const std::vector<std::string> common{"--no-images", "--variant-timeout", "8"};

  std::vector<std::string> args{"sweep", kSweepFixture.string(), "--out", out.string()};
  args.insert(args.end(), common.begin(), common.end());
  ::setenv("HYBRIDBENCH_TEST_HANG_VARIANT", hang.c_str(), 1);
  ::setenv("HYBRIDBENCH_TEST_CRASH_VARIANT", crash.c_str(), 1);
  const RunResult r = run(args);
  ::unsetenv("HYBRIDBENCH_TEST_HANG_VARIANT");
  ::unsetenv("HYBRIDBENCH_TEST_CRASH_VARIANT");
  EXPECT_EQ(r.exitCode, 3) << r.out << r.err;
  EXPECT_NE(r.err.find("2 variant(s) timed out or crashed"), std::string::npos) << r.err;
  // The whole command that runs them again: the sweep's own options, --resume and --retry-failed.
  const char* other = std::getenv("HYBRIDBENCH_TEST_BINARY");
  EXPECT_NE(r.err.find("run them again with: " + std::string(other && *other ? other : HYBRIDBENCH_BINARY) + " sweep " +
                       kSweepFixture.string() + " --resume --retry-failed --out " + out.string() +
                       " --no-images --variant-timeout 8\n"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.out.find("variant \"" + hang + "\" timed out after"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("variant \"" + crash + "\" crashed after"), std::string::npos) << r.out;
  EXPECT_EQ(processesMentioning(out.string()), std::vector<std::string>{});  // no worker left behind

  const json results = readJson(out / "results.json");
  ASSERT_FALSE(results.is_discarded());
  ASSERT_EQ(results["runs"].size(), variants.size()) << results["runs"].dump();
  for (size_t i = 0; i < variants.size(); ++i) {
    const json& run = results["runs"][i];
    EXPECT_EQ(run["name"], variants[i]["name"]);
    const std::string want = i == 1 ? "timeout" : i == 2 ? "crashed" : "ok";
    EXPECT_EQ(run.value("status", ""), want) << run.dump();
  }
  const json& timedOut = results["runs"][1];
  EXPECT_EQ(timedOut.value("last_step", ""), "warm-up");
  EXPECT_EQ(timedOut.value("timeout_s", 0.0), kTimeoutS);
  EXPECT_GE(timedOut.value("seconds", 0.0), kTimeoutS);
  EXPECT_LT(timedOut.value("seconds", 0.0), kTimeoutS + 2.0);  // the watchdog looks once a second
  EXPECT_NE(timedOut.value("process", "").find("signal 9"), std::string::npos) << timedOut.dump();  // SIGKILL
  const json& crashed = results["runs"][2];
  EXPECT_EQ(crashed.value("last_step", ""), "warm-up");
  EXPECT_NE(crashed.value("process", "").find("signal 6"), std::string::npos) << crashed.dump();  // SIGABRT
  EXPECT_LT(crashed.value("seconds", 1e9), kGraceS);
  // results.csv holds the same runs.
  const std::string csv = readFile(out / "results.csv");
  for (const json& v : variants) EXPECT_NE(csv.find(v["name"].get<std::string>()), std::string::npos) << csv;

  // The variants before and after, in their first and their fresh processes, count what an
  // undisturbed sweep counts.
  std::vector<std::string> plain{"sweep", kSweepFixture.string(), "--out", undisturbed.string()};
  plain.insert(plain.end(), common.begin(), common.end());
  const RunResult u = run(plain);
  ASSERT_EQ(u.exitCode, 0) << u.out << u.err;
  const json reference = readJson(undisturbed / "results.json");
  ASSERT_EQ(reference["runs"].size(), variants.size());
  for (size_t i : {size_t(0), size_t(3)}) {
    EXPECT_EQ(countsOf(results["runs"][i]), countsOf(reference["runs"][i])) << variants[i]["name"];
    EXPECT_FALSE(countsOf(results["runs"][i]).empty());
  }

  // --resume keeps the two unless asked; --resume --retry-failed runs them and nothing else.
  std::vector<std::string> resume = args;
  resume.push_back("--resume");
  const RunResult kept = run(resume);
  EXPECT_EQ(kept.exitCode, 3) << kept.out << kept.err;
  EXPECT_NE(kept.out.find("resume: 2 of 4 variants already done, 2 that timed out or crashed kept"), std::string::npos)
      << kept.out;
  resume.push_back("--retry-failed");
  const RunResult retried = run(resume);
  EXPECT_EQ(retried.exitCode, 0) << retried.out << retried.err;
  const json after = readJson(out / "results.json");
  ASSERT_EQ(after["runs"].size(), variants.size());
  for (size_t i = 0; i < variants.size(); ++i) EXPECT_EQ(after["runs"][i].value("status", ""), "ok") << i;
  for (size_t i : {size_t(0), size_t(3)}) EXPECT_EQ(after["runs"][i], results["runs"][i]) << "carried over verbatim";
  EXPECT_EQ(countsOf(after["runs"][1]), countsOf(reference["runs"][1]));
  EXPECT_EQ(countsOf(after["runs"][2]), countsOf(reference["runs"][2]));
}

TEST_F(SweepWatchdog, RetryFailedWithoutResumeIsOneLineExit2) {
  const RunResult r = run({"sweep", kSweepFixture.string(), "--out", (dir / "out").string(), "--retry-failed"});
  EXPECT_EQ(r.exitCode, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("--retry-failed"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out" / "results.json"));
}

}  // namespace
