// What an interrupted sweep tells its user, end to end on lavapipe: the whole command that
// continues it (options that shape the results included, a folder with a space quoted for the
// shell), which runs as printed and finishes the sweep; and a --resume with another config is
// refused with the first field that differs and both values.
#include <signal.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tool_process.h"

// A named namespace: the unity build puts this file beside others with helpers of the same names.
namespace sweep_resume_cli_test {

using namespace hb::testing;

class SweepResume : public ToolTest {};

// The text after `marker` up to the end of its line; empty when absent.
std::string restOfLine(const std::string& text, const std::string& marker) {
  const size_t at = text.find(marker);
  if (at == std::string::npos) return "";
  const size_t from = at + marker.size();
  return text.substr(from, text.find('\n', from) - from);
}

TEST_F(SweepResume, AnInterruptedSweepPrintsTheWholeCommandThatContinuesIt) {
  // Three of the tiny config's variants at a size of the command line's, not the config's: a
  // resume without --size would run another config.
  json config = readJson(hb::testing::kSweepFixture);
  config["variants"].erase(3);
  const fs::path configPath = dir / "resume-tiny.json";
  writeFile(configPath, config.dump(1));
  const fs::path out = dir / "out dir";  // a space: the printed command must quote it
  // 30 measured frames: ~2 s a variant on lavapipe, so the signal lands before the end.
  const std::vector<std::string> args{"sweep", configPath.string(), "--out", out.string(), "--size",
                                      "64x36", "--frames",          "30",    "--no-images"};
  const pid_t first = start(args);
  ASSERT_TRUE(waitForRuns(first, out, 1));
  kill(first, SIGINT);
  const RunResult interrupted = wait(first);
  ASSERT_EQ(interrupted.exitCode, 130) << interrupted.out << interrupted.err;
  const size_t done = readJson(out / "results.json")["runs"].size();
  ASSERT_LT(done, config["variants"].size()) << "the sweep finished before the signal: make its variants longer";

  const std::string binary = std::getenv("HYBRIDBENCH_TEST_BINARY") && *std::getenv("HYBRIDBENCH_TEST_BINARY")
                                 ? std::getenv("HYBRIDBENCH_TEST_BINARY")
                                 : HYBRIDBENCH_BINARY;
  const std::string command = restOfLine(interrupted.out, "continue with: ");
  EXPECT_EQ(command, binary + " sweep " + configPath.string() + " --resume --out '" + out.string() +
                         "' --frames 30 --no-images --size 64x36")
      << interrupted.out;

  // The resume of the old suggestion, "--resume --out DIR", lacks --size: refused, with the field.
  const RunResult partial =
      run({"sweep", configPath.string(), "--resume", "--out", out.string(), "--frames", "30", "--no-images"});
  EXPECT_EQ(partial.exitCode, 2) << partial.out << partial.err;
  EXPECT_EQ(std::count(partial.err.begin(), partial.err.end(), '\n'), 1) << partial.err;
  EXPECT_NE(partial.err.find("resolution differs (interrupted sweep: [64,36], this one: [96,54])"), std::string::npos)
      << partial.err;
  EXPECT_EQ(readJson(out / "results.json")["runs"].size(), done) << "a refused resume keeps the results";

  // The printed command, run by a shell as a user pastes it, finishes the sweep.
  const fs::path script = dir / "resume.sh", log = dir / "resume.log";
  writeFile(script, command + "\n");
  const std::string shell = "HYBRIDBENCH_VALIDATION=1 bash '" + script.string() + "' > '" + log.string() + "' 2>&1";
  const int status = std::system(shell.c_str());
  const std::string resumed = readFile(log);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << resumed;
  EXPECT_NE(resumed.find("resume: " + std::to_string(done) + " of 3 variants already done"), std::string::npos)
      << resumed;
  EXPECT_EQ(resumed.find("validation:"), std::string::npos) << resumed;
  const json results = readJson(out / "results.json");
  ASSERT_EQ(results["runs"].size(), 3u);
  for (const json& run : results["runs"]) EXPECT_EQ(run.value("status", ""), "ok") << run.dump();
  EXPECT_EQ(results["context"]["config"]["defaults"]["resolution"], json::array({64, 36}));
}

}  // namespace sweep_resume_cli_test
