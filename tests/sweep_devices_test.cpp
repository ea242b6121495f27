// `sweep --device all|LIST`: several devices sweep at once (issue #18). End to end, the built tool on
// the device present (lavapipe on CI).
#include <algorithm>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tool_process.h"

namespace {

using namespace hb::testing;

class SweepDevices : public ToolTest {};

// Several devices sweep at once, one thread and one folder each (issue #18). CI has one device,
// so the test names it twice: two sweeps on one device at the same time must each be complete and
// count the same rays as each other (every count is deterministic; only times may differ).
TEST_F(SweepDevices, SeveralDevicesSweepConcurrentlyIntoOneFolderEachWithEqualCounts) {
  const fs::path out = dir / "out";
  const RunResult r = run({"sweep", kSweepFixture.string(), "--device", "0,0", "--out", out.string(), "--no-images",
                           "--frames", "1", "--warmup", "0"});
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("sweep on 2 devices concurrently"), std::string::npos) << r.out;
  std::vector<fs::path> folders;
  for (const auto& e : fs::directory_iterator(out)) folders.push_back(e.path());
  std::sort(folders.begin(), folders.end());
  ASSERT_EQ(folders.size(), 2u);
  EXPECT_EQ(folders[0].filename().string().rfind("0-", 0), 0u) << folders[0];
  EXPECT_EQ(folders[1].filename().string().rfind("1-", 0), 0u) << folders[1];
  const json a = readJson(folders[0] / "results.json"), b = readJson(folders[1] / "results.json");
  ASSERT_FALSE(a.is_discarded());
  ASSERT_FALSE(b.is_discarded());
  ASSERT_EQ(a["context"]["concurrent_with"].size(), 1u);
  // One device named twice: both sweeps say their times include the other's work, once on stderr.
  EXPECT_TRUE(a["context"].contains("timing_caveat_shared_device"));
  EXPECT_TRUE(b["context"].contains("timing_caveat_shared_device"));
  size_t warnings = 0;
  for (size_t at = r.err.find("is named more than once"); at != std::string::npos;
       at = r.err.find("is named more than once", at + 1))
    ++warnings;
  EXPECT_EQ(warnings, 1u) << r.err;
  EXPECT_NE(a["context"]["concurrent_with"][0].get<std::string>().rfind("1: ", 0), std::string::npos);
  ASSERT_EQ(a["runs"].size(), b["runs"].size());
  ASSERT_EQ(a["runs"].size(), readJson(kSweepFixture)["variants"].size());
  for (size_t i = 0; i < a["runs"].size(); ++i) {
    const json &ra = a["runs"][i], &rb = b["runs"][i];
    ASSERT_EQ(ra.value("status", ""), "ok") << ra.dump();
    ASSERT_EQ(rb.value("status", ""), "ok") << rb.dump();
    EXPECT_EQ(ra["rays"], rb["rays"]) << ra.value("name", "");
    EXPECT_EQ(ra["culling"], rb["culling"]) << ra.value("name", "");
  }
  // Every line a device's sweep wrote names that device.
  std::istringstream lines(r.out);
  for (std::string line; std::getline(lines, line);) {
    if (line.find("variants,") != std::string::npos || line.find("] [") != std::string::npos) {
      EXPECT_TRUE(line.rfind("[0: ", 0) == 0 || line.rfind("[1: ", 0) == 0) << line;
    }
  }

  const RunResult bad = run({"sweep", kSweepFixture.string(), "--device", "0,", "--out", (dir / "x").string()});
  EXPECT_EQ(bad.exitCode, 2) << bad.err;
}

}  // namespace
