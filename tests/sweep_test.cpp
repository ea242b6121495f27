// End-to-end tests of `hybridbench sweep`, `tables` and `compare`: they run the built tool
// (HYBRIDBENCH_BINARY) as a child process on the tiny config tests/fixtures/sweep-tiny.json and
// hold its output files to docs/results-format.md: every finished variant is written at once,
// an interrupted sweep (SIGINT/SIGTERM, exit 130) keeps exactly its finished runs and --resume
// completes it without re-running them, a variant the renderer refuses is recorded as an error
// and the sweep goes on, and compare calls a file the same as itself and flags a slowdown.
// Every child runs with HYBRIDBENCH_VALIDATION=1 and must print no "validation:" line. Each
// sweep takes a few seconds on lavapipe (2 cores).
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include "tool_process.h"

#ifndef HYBRIDBENCH_SOURCE_DIR
#error "HYBRIDBENCH_SOURCE_DIR must name the source tree (for tests/fixtures)"
#endif

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

// A child that runs longer than this is hung: the longest sweep here takes ~20 s on lavapipe.
const std::vector<std::string> kPasses = {"depth_prepass", "light_culling", "shadows", "shading"};

using hb::testing::kSweepFixture;
using hb::testing::readFile;
using hb::testing::readJson;
using hb::testing::RunResult;
using hb::testing::writeFile;

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

// One CSV record (RFC 4180 quoting: "a, b" and "" for a quote).
std::vector<std::string> csvFields(const std::string& line) {
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

std::vector<std::string> runNames(const json& results) {
  std::vector<std::string> names;
  for (const json& run : results.value("runs", json::array())) names.push_back(run.value("name", ""));
  return names;
}

std::vector<std::string> variantNames(const json& config) {
  std::vector<std::string> names;
  for (const json& v : config["variants"]) names.push_back(v["name"]);
  return names;
}

class Sweep : public hb::testing::ToolTest {
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
void expectTimingBlock(const json& t, size_t frames, const std::string& what) {
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
void expectCompleteRun(const json& run, const json& variant, size_t frames) {
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

// Ray accounting, culling, accuracy and ray throughput of a finished run (docs/results-format.md).
void expectAnalysis(const json& run) {
  SCOPED_TRACE("run \"" + run.value("name", std::string()) + "\"");
  const json& p = run["params"];
  ASSERT_TRUE(run.contains("rays"));
  const json& rays = run["rays"];
  EXPECT_EQ(rays.value("adds_up", false), true);
  const uint64_t candidates = rays["candidates"], traced = rays["traced"], oracle = rays["oracle"];
  uint64_t buckets = 0;
  for (const char* b : {"culled_by_tile", "dropped_by_overflow", "culled_by_range", "culled_by_normal", "at_light",
                        "no_shadow", "traced"})
    buckets += rays[b].get<uint64_t>();
  EXPECT_EQ(candidates, buckets);
  // The histogram counts non-sky pixels by rays traced: its total is the pixel count (each pixel
  // is a candidate for each of the scene's 10 lights) and its first moment is the rays traced.
  uint64_t pixels = 0, moment = 0;
  const std::vector<uint64_t> hist = rays["per_pixel_histogram"];
  for (size_t k = 0; k < hist.size(); ++k) pixels += hist[k], moment += k * hist[k];
  EXPECT_EQ(candidates, 10 * pixels);
  EXPECT_EQ(traced, moment);
  EXPECT_GT(pixels, 0u);
  EXPECT_LE(pixels, uint64_t(96) * 54);
  EXPECT_EQ(rays["efficiency"].get<double>(), double(oracle) / double(traced));  // oracle / traced
  if (!p["light_culling"].get<bool>() && p["normal_culling"] == "off" && !p["range_test"].get<bool>()) {
    // Nothing culls: every candidate is traced (no light sits on a surface, all cast shadows),
    // and the oracle is a subset of the candidates, so efficiency <= 1 here. Normal culling may
    // trace fewer rays than the oracle (a wrong reconstructed normal), so nothing is asserted there.
    EXPECT_EQ(traced, candidates);
    EXPECT_LE(oracle, traced);
    EXPECT_LE(rays["efficiency"].get<double>(), 1.0);
  }

  ASSERT_TRUE(run.contains("culling"));
  const json& c = run["culling"];
  EXPECT_EQ(c.value("false_negatives", -1), 0);  // the culling is conservative
  const uint32_t ts = p["tile_size"];
  EXPECT_EQ(c.value("tiles", 0u), ((96 + ts - 1) / ts) * ((54 + ts - 1) / ts));
  for (const char* key :
       {"lights_per_tile_mean", "lights_per_tile_max", "overflow_tiles", "false_positive_rate", "memory_bytes"})
    EXPECT_TRUE(c.contains(key) && c[key].is_number()) << key;

  ASSERT_TRUE(run.contains("accuracy"));
  const json& a = run["accuracy"];
  ASSERT_TRUE(a.contains("world_pos_rel_error"));
  EXPECT_TRUE(std::isfinite(a["world_pos_rel_error"].get<double>()));
  EXPECT_EQ(a.contains("normal_angular_error_deg"), p["normal_culling"] != "off");
  // Against the no-culling reference render (10 lights: one tile list holds them all).
  ASSERT_TRUE(a.contains("image_error") && a["image_error"].is_number()) << a.dump();
  const double flip = a["image_error"];
  EXPECT_GE(flip, 0.0);
  EXPECT_LE(flip, 1.0);  // LDR-FLIP is in [0, 1]
  ASSERT_TRUE(a.contains("shadow_mismatches")) << a.dump();
  const json& m = a["shadow_mismatches"];
  const uint64_t dark = m["wrongly_dark"], lit = m["wrongly_lit"], pairs = m["pairs_compared"];
  EXPECT_GT(pairs, 0u);
  EXPECT_LE(dark + lit, pairs);
  if (!p["light_culling"].get<bool>() && p["normal_culling"] == "off" && !p["range_test"].get<bool>() &&
      p["backend"] == "auto") {
    // These are the reference's own parameters: the same pipelines on the same inputs render the
    // same frame, so nothing may differ.
    EXPECT_EQ(flip, 0.0);
    EXPECT_EQ(dark, 0u);
    EXPECT_EQ(lit, 0u);
  }

  // raybench.rays is rays.traced as sweep_device writes it, so this checks the results' plumbing
  // only; that raybench re-traces exactly the rays the shadow pass traced (and counts the same
  // visible ones, pixel by pixel) is tests/raybench_gpu_test.cpp (RayBenchRays).
  ASSERT_TRUE(run.contains("raybench"));
  EXPECT_EQ(run["raybench"]["rays"].get<double>(), double(traced));
  EXPECT_GE(run["raybench"]["repetitions"].get<int>(), 1);
  EXPECT_GT(run["raybench"]["rays_per_s"].get<double>(), 0.0);

  const std::string backend = p["backend"];
  if (backend != "auto") {
    EXPECT_EQ(run.value("backend", ""), backend);
  }
}

// results.csv: a header, then per run one row for "frame" and one per pass (one row in all for
// a run that is not ok), each with the header's field count; every run of results.json appears.
void expectCsvMatches(const std::string& csv, const json& results) {
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

TEST_F(Sweep, TinySweepWritesCompleteResultsCsvAndTables) {
  const fs::path out = dir / "out";
  const RunResult r = run({"sweep", kSweepFixture.string(), "--out", out.string(), "--no-images"});
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  const json config = readJson(kSweepFixture);
  const json results = readJson(out / "results.json");
  ASSERT_FALSE(results.is_discarded());

  EXPECT_EQ(results.value("schema_version", 0), 1);
  const json& ctx = results["context"];
  EXPECT_EQ(ctx["tool"].value("name", ""), "hybridbench");
  EXPECT_FALSE(ctx["tool"].value("version", "").empty());
  EXPECT_TRUE(ctx["tool"].contains("git"));
  EXPECT_FALSE(ctx["host"].value("hostname", "").empty());
  EXPECT_GE(ctx["host"].value("cores", 0), 1);
  for (const char* key : {"name", "uuid", "type", "driver", "api_version", "rt_backend"})
    EXPECT_TRUE(ctx["device"].contains(key) && ctx["device"][key].is_string()) << key;
  EXPECT_GT(ctx["device"].value("timestamp_period_ns", 0.0), 0.0);
  EXPECT_EQ(ctx["scene"].value("name", ""), "atrium");
  const std::string sha = ctx["scene"].value("sha256", "");
  EXPECT_EQ(sha.size(), 64u) << sha;
  EXPECT_EQ(sha.find_first_not_of("0123456789abcdef"), std::string::npos) << sha;
  EXPECT_GT(ctx["scene"].value("triangles", 0), 0);
  EXPECT_EQ(ctx["scene"].value("lights", 0), 10);
  // 96x54 is below the CPU cap (480x270) and 1+3 frames below its 2+5: nothing is lowered.
  EXPECT_EQ(ctx["resolution"], json::array({96, 54}));
  EXPECT_EQ(ctx["config"].value("name", ""), "sweep-tiny");
  EXPECT_EQ(ctx["config"]["frames"], (json{{"warmup", 1}, {"measured", 3}}));
  EXPECT_EQ(variantNames(ctx["config"]), variantNames(config));

  ASSERT_EQ(runNames(results), variantNames(config));
  for (size_t i = 0; i < results["runs"].size(); ++i) {
    const json& run = results["runs"][i];
    const json variant = ctx["config"]["variants"][i];
    expectCompleteRun(run, variant, 3);
    // On a CPU device the warm-up is the configured count (the 0.5 s floor is for GPU clocks).
    EXPECT_EQ(run.value("warmup_frames", 0), 1);
    EXPECT_GT(run.value("warmup_s", -1.0), 0.0);
    expectAnalysis(run);
    EXPECT_FALSE(run.contains("images"));
  }
  for (const auto& e : fs::recursive_directory_iterator(out))
    EXPECT_NE(e.path().extension(), ".png") << "--no-images wrote " << e.path();

  expectCsvMatches(readFile(out / "results.csv"), results);
  const std::string tablesMd = readFile(out / "tables.md");
  EXPECT_NE(tablesMd.find("Table 5.1"), std::string::npos);

  // `tables` rebuilds the same tables from results.json.
  const RunResult md = run({"tables", (out / "results.json").string()});
  ASSERT_EQ(md.exitCode, 0) << md.err;
  EXPECT_NE(md.out.find("Table 5.1"), std::string::npos) << md.out;
  // `tables` prints tables.md followed by the accuracy-vs-time report (accuracy.md).
  const std::string accuracyMd = readFile(out / "accuracy.md");
  EXPECT_NE(accuracyMd.find("Pareto"), std::string::npos) << accuracyMd;
  EXPECT_EQ(md.out, tablesMd + "\n" + accuracyMd);
  const RunResult svg = run({"tables", (out / "results.json").string(), "--format", "svg"});
  ASSERT_EQ(svg.exitCode, 0) << svg.err;
  EXPECT_EQ(svg.out, readFile(out / "accuracy.svg"));
  const RunResult csv = run({"tables", (out / "results.json").string(), "--format", "csv"});
  ASSERT_EQ(csv.exitCode, 0) << csv.err;
  const std::vector<std::string> rows = lines(csv.out);
  ASSERT_GE(rows.size(), 2u) << csv.out;
  const size_t fields = csvFields(rows[0]).size();
  EXPECT_GE(fields, 3u) << rows[0];
  for (const std::string& row : rows) EXPECT_EQ(csvFields(row).size(), fields) << row;
  bool found51 = false;
  for (const std::string& row : rows) found51 |= csvFields(row)[0] == "5.1";
  EXPECT_TRUE(found51) << csv.out;

  // Several files of one device are read as one. The same variants twice are refused, unless
  // --allow-duplicates: then every run is there twice, each row named with its file (the
  // accuracy report has a row per run); another device is refused.
  const std::string file = (out / "results.json").string();
  const RunResult dup = run({"tables", file, file});
  EXPECT_EQ(dup.exitCode, 2) << dup.err;
  EXPECT_NE(dup.err.find("--allow-duplicates"), std::string::npos) << dup.err;
  const RunResult twice = run({"tables", file, file, "--allow-duplicates"});
  ASSERT_EQ(twice.exitCode, 0) << twice.err;
  const std::string name = results["runs"][0]["name"].get<std::string>();
  auto occurrences = [](const std::string& text, const std::string& row) {
    size_t n = 0;
    for (size_t at = text.find(row); at != std::string::npos; at = text.find(row, at + 1)) ++n;
    return n;
  };
  const size_t report = twice.out.find("## Accuracy vs frame time");
  ASSERT_NE(report, std::string::npos) << twice.out;
  EXPECT_EQ(occurrences(twice.out.substr(report), "| " + name + " [" + file + "] |"),
            2 * occurrences(accuracyMd, "| " + name + " |"))
      << twice.out;
  nlohmann::json other = results;
  other["context"]["device"]["name"] = "another GPU";
  std::ofstream(out / "other.json") << other.dump();
  const RunResult refused = run({"tables", (out / "results.json").string(), (out / "other.json").string()});
  EXPECT_EQ(refused.exitCode, 2);
  EXPECT_NE(refused.err.find("another GPU"), std::string::npos) << refused.err;
}

// scripts/ci-compare.sh, the recipe for a user's CI: sweeping the baseline's own config on the same
// device is no regression (exit 0, compare.md and a JUnit report written); against a baseline
// whose every time is a hundredth, the new run is 100x as slow: exit 1; a missing baseline: exit 2.
// The threshold is 900 % (below): lavapipe's frame times move with the machine's load, which a
// 5 % threshold would (rightly) call a change. The recipe at its defaults (5 %, --gate all) is
// tests/ci_compare_test.cpp, on a fixed GPU run and edited copies of it.
TEST_F(Sweep, CiCompareRecipePassesAgainstItselfAndFailsAgainstAFasterBaseline) {
  const fs::path base = dir / "base";
  // 8 frames a side: a U test of 3 against 3 cannot reach p < 0.05 however far apart they are.
  const RunResult sweep =
      run({"sweep", kSweepFixture.string(), "--no-images", "--frames", "8", "--out", base.string()});
  ASSERT_EQ(sweep.exitCode, 0) << sweep.err;
  const std::string script = std::string(HYBRIDBENCH_SOURCE_DIR) + "/scripts/ci-compare.sh";
  // lavapipe's frame times move with the machine's load: the same sweep twice on a 2-core machine
  // that was also compiling read 1.8x slower in one variant. The threshold is 900 % (10x), far
  // beyond that, and the "faster" baseline below is 100x faster, far beyond the threshold: the
  // test checks the recipe's plumbing and verdicts, not lavapipe's timing.
  auto recipe = [&](const fs::path& baseline, const fs::path& out) {
    const std::string cmd =
        "SWEEP_ARGS='--frames 8' COMPARE_ARGS='--threshold 900' HYBRIDBENCH_VALIDATION=1 HYBRIDBENCH='" +
        std::string(HYBRIDBENCH_BINARY) + "' bash '" + script + "' '" + baseline.string() + "' '' '" + out.string() +
        "' > '" + (out.string() + ".log") + "' 2>&1";
    fs::create_directories(out.parent_path());
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  EXPECT_EQ(recipe(base / "results.json", dir / "same"), 0) << readFile(dir / "same.log");
  EXPECT_NE(
      readFile(dir / "same" / "compare.md").find("regression (a frame or pass time slower beyond the threshold): no"),
      std::string::npos);
  // The JUnit report: frame test cases pass (a pass's own time may still move on lavapipe).
  const std::regex frameFailure(R"(name="frame" time="[0-9.]+">\s*<failure)");
  const std::string sameJunit = readFile(dir / "same" / "compare.junit.xml");
  EXPECT_NE(sameJunit.find("<testcase "), std::string::npos);
  EXPECT_FALSE(std::regex_search(sameJunit, frameFailure)) << sameJunit;
  EXPECT_EQ(readFile(dir / "same.log").find("validation:"), std::string::npos);

  json fast = readJson(base / "results.json");
  auto hundredth = [](json& stats) {  // 100x faster
    for (auto& [key, v] : stats.items())
      if (key == "samples") {
        for (json& x : v) x = x.get<double>() * 0.01;
      } else if (key != "cv" && v.is_number()) {
        v = v.get<double>() * 0.01;
      }
  };
  for (json& r : fast["runs"]) {
    hundredth(r["frame_ms"]);
    for (auto& [pass, stats] : r["passes"].items()) hundredth(stats);
  }
  writeFile(dir / "fast.json", fast.dump());
  EXPECT_EQ(recipe(dir / "fast.json", dir / "slow"), 1) << readFile(dir / "slow.log");
  EXPECT_TRUE(std::regex_search(readFile(dir / "slow" / "compare.junit.xml"), frameFailure));
  EXPECT_EQ(recipe(dir / "missing.json", dir / "none"), 2) << readFile(dir / "none.log");
}

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

// Every frame_ms and pass timing of results scaled by factor (cv is scale-free).
json scaled(json results, double factor) {
  auto scale = [factor](json& t) {
    for (const char* key : {"median", "mean", "stddev", "min", "max", "p95"})
      if (t.contains(key)) t[key] = t[key].get<double>() * factor;
    for (json& s : t["samples"]) s = s.get<double>() * factor;
  };
  for (json& run : results["runs"]) {
    if (run.value("status", "") != "ok") continue;
    scale(run["frame_ms"]);
    for (auto& [pass, t] : run["passes"].items()) scale(t);
  }
  return results;
}

TEST_F(Sweep, CompareCallsAFileTheSameAsItselfFlagsASlowdownAndRefusesAnotherScene) {
  const fs::path out = dir / "out";
  // 8 measured frames: compare needs >= 5 a side (kMinSamplesForVerdict) for any verdict but
  // "too noisy", and 8 a side make a complete separation significant (exact p = 2/C(16,8)).
  const RunResult sweep = run({"sweep", kSweepFixture.string(), "--out", out.string(), "--no-images", "--frames", "8"});
  ASSERT_EQ(sweep.exitCode, 0) << sweep.out << sweep.err;
  const fs::path a = out / "results.json";
  const json results = readJson(a);
  ASSERT_FALSE(results.is_discarded());

  // Against itself: the U test sees identical samples (p = 1), so no row may read slower or
  // faster; a row reads "same" when both sides have >= 5 samples and cv <= 0.10 (compare.h),
  // else "too noisy". The expected verdict per row follows from the file's own n and cv.
  const RunResult self = run({"compare", a.string(), a.string(), "--json"});
  ASSERT_EQ(self.exitCode, 0) << self.out << self.err;
  const json report = json::parse(self.out, nullptr, false);
  ASSERT_FALSE(report.is_discarded()) << self.out;
  EXPECT_FALSE(report.value("regression", true));
  bool anySame = false;
  for (const json& row : report["rows"]) {
    const json* run = nullptr;
    for (const json& r : results["runs"])
      if (r["name"] == row["variant"]) run = &r;
    ASSERT_NE(run, nullptr) << row.dump();
    const json& t = row["pass"] == "frame" ? run->at("frame_ms") : run->at("passes").at(row["pass"].get<std::string>());
    const bool quiet = t["samples"].size() >= 5 && t["cv"].get<double>() <= 0.10;
    // lavapipe is a CPU device: its per-pass rows are "not timed" (compare.h); frames compare.
    const bool cpu = results["context"]["device"]["type"] == "cpu";
    if (cpu && row["pass"] != "frame") {
      EXPECT_EQ(row.value("verdict", ""), "not timed") << row.dump();
      continue;
    }
    EXPECT_EQ(row.value("verdict", ""), quiet ? "same" : "too noisy") << row.dump();
    anySame |= quiet;
  }
  EXPECT_EQ(report["rows"].size(), results["runs"].size() * (1 + kPasses.size()));
  const RunResult selfText = run({"compare", a.string(), a.string()});
  EXPECT_EQ(selfText.exitCode, 0) << selfText.err;
  if (anySame) {
    EXPECT_NE(selfText.out.find("same"), std::string::npos) << selfText.out;
  }

  // 30 % slower everywhere. When every frame sample of B exceeds every one of A (factor above
  // each run's max/min), U = 0 and the exact two-sided p = 2/C(16,8) = 1.6e-4 < alpha 0.05, and
  // the ratio of medians is the factor > 1.05: "slower", a regression, exit 1. The factor is
  // 1.3 unless a run's own spread is wider (then just above it, so the samples cannot overlap).
  double factor = 1.3;
  for (const json& run : results["runs"])
    factor = std::max(factor, 1.01 * run["frame_ms"]["max"].get<double>() / run["frame_ms"]["min"].get<double>());
  const fs::path b = dir / "slower.json";
  writeFile(b, scaled(results, factor).dump(1));
  const RunResult slower = run({"compare", a.string(), b.string()});
  EXPECT_EQ(slower.exitCode, 1) << slower.out << slower.err;
  EXPECT_NE(slower.out.find("slower"), std::string::npos) << slower.out;

  // Another scene's results are refused (one line, exit 2) unless forced.
  json other = results;
  other["context"]["scene"]["sha256"] = std::string(64, '0');
  const fs::path c = dir / "other-scene.json";
  writeFile(c, other.dump(1));
  const RunResult refused = run({"compare", a.string(), c.string()});
  EXPECT_EQ(refused.exitCode, 2) << refused.out << refused.err;
  EXPECT_EQ(std::count(refused.err.begin(), refused.err.end(), '\n'), 1) << refused.err;
  EXPECT_NE(refused.err.find("sha256"), std::string::npos) << refused.err;
  const RunResult forced = run({"compare", a.string(), c.string(), "--force"});
  EXPECT_NE(forced.exitCode, 2) << forced.err;
  EXPECT_EQ(forced.exitCode, 0) << forced.out << forced.err;  // identical samples: no regression
}

// The 64-lights variant fails (only 32 per tile is implemented); the depth-sliced one, placed
// between it and the last, runs as any other.
TEST_F(Sweep, UnsupportedVariantIsRecordedAsAnErrorAndTheSweepGoesOn) {
  const json fixture = readJson(kSweepFixture);
  const json variants = {fixture["variants"][0],
                         {{"name", "64 lights per tile"}, {"params", {{"max_lights_per_tile", 64}}}},
                         {{"name", "4 depth slices"}, {"params", {{"depth_slices", 4}}}},
                         fixture["variants"][1]};
  const fs::path config = configWith("sweep-unsupported", variants);
  const fs::path out = dir / "out";
  const RunResult r = run({"sweep", config.string(), "--out", out.string(), "--no-images"});
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
  const json results = readJson(out / "results.json");
  ASSERT_FALSE(results.is_discarded());
  ASSERT_EQ(runNames(results), variantNames(json{{"variants", variants}}));
  const json& runs = results["runs"];
  for (size_t i : {size_t(0), size_t(2), size_t(3)})
    expectCompleteRun(runs[i], results["context"]["config"]["variants"][i], 3);
  EXPECT_EQ(runs[2]["culling"].value("depth_slices", 0), 4) << runs[2].dump();
  const std::map<size_t, std::string> refused = {{1, "max_lights_per_tile"}};
  for (const auto& [i, key] : refused) {
    SCOPED_TRACE(runs[i].dump());
    EXPECT_EQ(runs[i].value("status", ""), "error");
    const std::string error = runs[i].value("error", "");
    EXPECT_NE(error.find(key), std::string::npos) << error;
    EXPECT_EQ(runs[i]["params"], results["context"]["config"]["variants"][i]["params"]);
    EXPECT_FALSE(runs[i].contains("frame_ms"));
    EXPECT_NE(r.out.find(runs[i].value("name", "")), std::string::npos) << r.out;
  }
  EXPECT_NE(r.out.find("1 variant(s) failed"), std::string::npos) << r.out;
  expectCsvMatches(readFile(out / "results.csv"), results);
  const RunResult tables = run({"tables", (out / "results.json").string()});
  EXPECT_EQ(tables.exitCode, 0) << tables.err;
}

// Ambient occlusion per variant (params.effects): each run carries its method's passes, its errors
// against the ray tracer (0 against itself) and the 1,024-ray reference, the LDM's memory and no overflow;
// the tables print the AO table and the accuracy report judges the sweep by the AO error.
TEST_F(Sweep, AmbientOcclusionVariantsCarryTheirErrorsAndPrintTheAoTable) {
  auto ao = [](json settings) { return json{{"effects", {{"ambient_occlusion", settings}}}}; };
  const json variants = {{{"name", "ldm 16 x 64^2"}, {"params", ao({{"directions", 16}, {"ldm_resolution", 64}})}},
                         {{"name", "ldm 16 x 64^2, cas"},
                          {"params", ao({{"directions", 16}, {"ldm_resolution", 64}, {"ldm_list", "cas"}})}},
                         {{"name", "raytraced 16"}, {"params", ao({{"method", "raytraced"}, {"directions", 16}})}},
                         {{"name", "reference 64"}, {"params", ao({{"method", "reference"}, {"samples", 64}})}}};
  const fs::path config = configWith("sweep-ao", variants);
  const fs::path out = dir / "out";
  const RunResult r = run({"sweep", config.string(), "--out", out.string(), "--no-images"});
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  const json results = readJson(out / "results.json");
  ASSERT_EQ(runNames(results), variantNames(json{{"variants", variants}}));
  for (const json& run : results["runs"]) {
    SCOPED_TRACE(run.value("name", ""));
    ASSERT_EQ(run.value("status", ""), "ok") << run.dump();
    const json& a = run["ambient_occlusion"];
    const std::string method = a.value("method", "");
    EXPECT_TRUE(run["passes"].contains("ambient_occlusion"));
    EXPECT_EQ(run["passes"].contains("ldm_build"), method == "ldm");
    EXPECT_GT(a["vs_reference"].value("pixels", 1), 0);
    EXPECT_EQ(a["vs_raytraced"].value("itself", false), method == "raytraced");
    // The analysis frame's reference takes 1,024 rays: a 64-ray reference run is measured against it.
    EXPECT_FALSE(a["vs_reference"].value("itself", false));
    if (method == "reference") {
      EXPECT_GT(a["vs_reference"].value("mae", 0.0), 0.0);
    }
    if (method == "ldm") {
      EXPECT_EQ(a["ldm"].value("overflow", 1), 0);
      EXPECT_LE(a["memory_bytes"].value("ldm_links", 0.0), 1.1 * a["ldm"].value("exact_bytes", 0.0));
      EXPECT_GE(a["memory_bytes"].value("ldm_links", 0.0), a["ldm"].value("exact_bytes", 0.0));
    }
  }
  // Both LDM variants hold the same depths (the same build, another list layout): the same AO.
  EXPECT_EQ(results["runs"][0]["ambient_occlusion"]["vs_raytraced"]["mae"],
            results["runs"][1]["ambient_occlusion"]["vs_raytraced"]["mae"]);
  const RunResult tables = run({"tables", (out / "results.json").string()});
  EXPECT_EQ(tables.exitCode, 0) << tables.err;
  EXPECT_NE(tables.out.find("## Ambient occlusion (layered depth maps)"), std::string::npos) << tables.out;
  EXPECT_NE(tables.out.find("AO error (MAE vs the Monte Carlo reference)"), std::string::npos) << tables.out;
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
