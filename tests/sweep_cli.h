// What the end-to-end sweep tests (sweep_*_cli_test.cpp) share: the Sweep fixture, which runs the
// built tool on the tiny config tests/fixtures/sweep-tiny.json, and the checks that hold its output
// files to docs/results-format.md (a finished run's record, its timing blocks, results.csv).
#pragma once
#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tool_process.h"

// A named namespace: one fixture class for the suite across files (GoogleTest requires it), and
// the tests build in unity batches, where anonymous namespaces of several files meet.
namespace hb::sweep_test {

using namespace hb::testing;

// The passes of the tiny config's frame, each timed.
inline const std::vector<std::string> kPasses = {"depth_prepass", "light_culling", "shadows", "shading"};

inline std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

// One CSV record (RFC 4180 quoting: "a, b" and "" for a quote).
inline std::vector<std::string> csvFields(const std::string& line) {
  std::vector<std::string> f(1);
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
      f.back() += '"';
      ++i;
    } else if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      f.emplace_back();
    } else {
      f.back() += c;
    }
  }
  return f;
}

inline std::vector<std::string> runNames(const json& results) {
  std::vector<std::string> names;
  for (const json& run : results.value("runs", json::array())) names.push_back(run.value("name", ""));
  return names;
}

inline std::vector<std::string> variantNames(const json& config) {
  std::vector<std::string> names;
  for (const json& v : config["variants"]) names.push_back(v["name"]);
  return names;
}

class Sweep : public ToolTest {
 protected:
  // The fixture config with its variants replaced, written into the scratch directory.
  fs::path configWith(const std::string& name, const json& variants) {
    json c = readJson(kSweepFixture);
    c["name"] = name;
    c["variants"] = variants;
    const fs::path p = dir / (name + ".json");
    writeFile(p, c.dump(1));
    return p;
  }
};

// The summary of a timing block: every key of docs/results-format.md, samples of the stated length, and
// aggregates consistent with the samples.
inline void expectTimingBlock(const json& t, size_t frames, const std::string& what) {
  SCOPED_TRACE(what);
  for (const char* key : {"median", "mean", "stddev", "cv", "min", "max", "p95"}) {
    ASSERT_TRUE(t.contains(key) && t[key].is_number()) << key << " in " << t.dump();
  }
  ASSERT_TRUE(t.contains("samples") && t["samples"].is_array());
  ASSERT_EQ(t["samples"].size(), frames);
  std::vector<double> s = t["samples"].get<std::vector<double>>();
  for (double v : s) EXPECT_TRUE(std::isfinite(v) && v >= 0) << v;
  std::sort(s.begin(), s.end());
  // min, max and (for an odd count) the median are samples themselves: exact. The mean lies in
  // [min, max] up to the round-off of a sum of n doubles (n ulps of max; 1e-12 relative covers it).
  EXPECT_EQ(t["min"].get<double>(), s.front());
  EXPECT_EQ(t["max"].get<double>(), s.back());
  if (frames % 2 == 1) {
    EXPECT_EQ(t["median"].get<double>(), s[frames / 2]);
  }
  const double slack = 1e-12 * s.back();
  for (const char* key : {"median", "mean", "p95"}) {
    EXPECT_GE(t[key].get<double>(), s.front() - slack) << key;
    EXPECT_LE(t[key].get<double>(), s.back() + slack) << key;
  }
  EXPECT_GE(t["stddev"].get<double>(), 0.0);
}

// A finished run (status ok) as the sweep writes it; `params` is the variant's entry in the config.
inline void expectCompleteRun(const json& run, const json& variant, size_t frames) {
  const std::string name = run.value("name", "");
  SCOPED_TRACE("run \"" + name + "\"");
  ASSERT_EQ(run.value("status", ""), "ok") << run.value("error", "");
  EXPECT_FALSE(run.contains("error"));
  EXPECT_EQ(run["params"], variant["params"]);
  EXPECT_EQ(run.value("frames", 0u), frames);
  ASSERT_TRUE(run.contains("frame_ms"));
  expectTimingBlock(run["frame_ms"], frames, "frame_ms");
  ASSERT_TRUE(run.contains("passes") && run["passes"].is_object());
  std::set<std::string> passes;
  for (const auto& [pass, t] : run["passes"].items()) passes.insert(pass);
  EXPECT_EQ(passes, std::set<std::string>(kPasses.begin(), kPasses.end()));
  for (const std::string& pass : kPasses) {
    ASSERT_TRUE(run["passes"].contains(pass)) << pass;
    expectTimingBlock(run["passes"][pass], frames, pass);
  }
  // The passes are disjoint intervals inside each frame's interval (gpu_timer.cpp: the frame's
  // stamps bracket every pass's), so per frame the pass times add up to at most the frame time.
  // Each time is an integer tick count scaled once (1 rounding), the sum of 4 adds 3 more:
  // 8 ulps of the frame time bound the round-off; 1e-12 relative is far above that.
  for (size_t i = 0; i < frames; ++i) {
    double sum = 0;
    for (const std::string& pass : kPasses) sum += run["passes"][pass]["samples"][i].get<double>();
    const double frame = run["frame_ms"]["samples"][i];
    EXPECT_LE(sum, frame * (1 + 1e-12)) << "frame " << i;
  }
}

// results.csv: a header, then per run one row for "frame" and one per pass (one row in all for
// a run that is not ok), each with the header's field count; every run of results.json appears.
inline void expectCsvMatches(const std::string& csv, const json& results) {
  const std::vector<std::string> rows = lines(csv);
  ASSERT_FALSE(rows.empty());
  const std::vector<std::string> header = csvFields(rows[0]);
  const auto col = [&](const char* name) {
    return size_t(std::find(header.begin(), header.end(), name) - header.begin());
  };
  const size_t runCol = col("run"), passCol = col("pass"), samplesCol = col("samples"), statusCol = col("status");
  ASSERT_LT(std::max({runCol, passCol, samplesCol, statusCol}), header.size()) << rows[0];
  std::vector<std::vector<std::string>> expected;  // run, status, pass, samples
  for (const json& run : results["runs"]) {
    const std::string name = run["name"], status = run["status"];
    if (status != "ok") {
      expected.push_back({name, status, "", "0"});
      continue;
    }
    expected.push_back({name, status, "frame", std::to_string(run["frame_ms"]["samples"].size())});
    for (const auto& [pass, t] : run["passes"].items())
      expected.push_back({name, status, pass, std::to_string(t["samples"].size())});
  }
  ASSERT_EQ(rows.size(), expected.size() + 1) << csv;
  for (size_t i = 0; i < expected.size(); ++i) {
    const std::vector<std::string> f = csvFields(rows[i + 1]);
    ASSERT_EQ(f.size(), header.size()) << rows[i + 1];
    EXPECT_EQ((std::vector<std::string>{f[runCol], f[statusCol], f[passCol], f[samplesCol]}), expected[i])
        << rows[i + 1];
  }
}

}  // namespace hb::sweep_test
