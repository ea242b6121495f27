#include "report/compare.h"

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "report/xml_test_util.h"

#include "base/errors.h"
#include "config/config.h"
#include "report/stats.h"

namespace hb {
namespace {

using nlohmann::json;

// Frame times around `centerMs` with relative spread `cv`, Box-Muller on mt19937 (whose output is
// fixed by the standard, unlike std::normal_distribution's) so the samples are the same everywhere.
std::vector<double> noisyTimes(std::mt19937& rng, size_t n, double centerMs, double cv) {
  auto uniform = [&] { return (static_cast<double>(rng()) + 0.5) / 4294967296.0; };
  std::vector<double> v;
  for (size_t i = 0; i < n; ++i) {
    const double radius = std::sqrt(-2 * std::log(uniform()));
    const double g = radius * std::cos(2 * std::numbers::pi * uniform());
    v.push_back(centerMs * (1 + cv * g));
  }
  return v;
}

json statsBlock(const std::vector<double>& samples) { return toJson(summarize(samples), samples); }

// A minimal schema-1 results file: one run per (name, frame-time center), a "shadows" pass at
// 90 % of the frame.
json makeResults(const std::string& sceneSha, uint32_t seed, size_t n, double scale, double cv = 0.02) {
  std::mt19937 rng(seed);
  json runs = json::array();
  for (const auto& [name, center] : {std::pair<const char*, double>{"no_opt_t8", 16.0}, {"all_on_t8", 9.44}}) {
    runs.push_back({{"name", name},
                    {"params", {{"tile_size", 8}}},
                    {"frames", n},
                    {"frame_ms", statsBlock(noisyTimes(rng, n, center * scale, cv))},
                    {"passes",
                     {{"shadows", statsBlock(noisyTimes(rng, n, 0.9 * center * scale, cv))},
                      {"depth_prepass", statsBlock(noisyTimes(rng, n, 0.3, cv))}}},
                    {"status", "ok"}});
  }
  return {{"schema_version", 1},
          {"context",
           {{"device", {{"name", "Test GPU"}}},
            {"scene", {{"name", "atrium"}, {"sha256", sceneSha}}},
            {"resolution", {1920, 1080}},
            {"config", {{"scene", "atrium"}, {"resolution", {1920, 1080}}}}}},
          {"runs", runs}};
}

TEST(CompareResults, SameDistributionIsSameEverywhereAndNoRegression) {
  // Two independent draws (different seeds) of the same distribution, CV 2 %, 30 samples each.
  const json a = makeResults("abc", 1, 30, 1.0), b = makeResults("abc", 2, 30, 1.0);
  const CompareReport r = compareResults(a, b, {});
  ASSERT_EQ(r.rows.size(), 6u);  // 2 variants x (frame, depth_prepass, shadows)
  for (const CompareRow& row : r.rows) EXPECT_EQ(row.verdict, "same") << row.variant << row.pass;
  EXPECT_FALSE(r.regression);
  // Medians of 30 draws with CV 2 % have a standard error ~1.25 * 2 % / sqrt(30) = 0.46 %; the
  // ratio of two is within 4 of those (1.3 %) of 1 with probability > 0.99.
  EXPECT_NEAR(r.geomeanRatio, 1.0, 0.013);
  EXPECT_TRUE(r.warnings.empty());
}

TEST(CompareResults, AVariantMeasuredWhileThrottledIsAWarningNamingItsSideAndReasons) {
  const json a = makeResults("abc", 1, 30, 1.0);
  json b = makeResults("abc", 2, 30, 1.0);
  b["runs"][1]["telemetry"] = {{"available", true},
                               {"throttled", true},
                               {"throttle_reasons", {"sw_power_cap"}},
                               {"warning", "the GPU's clocks were held down (sw_power_cap)"}};
  b["runs"][0]["telemetry"] = {{"available", true}, {"throttled", false}, {"throttle_reasons", json::array()}};
  json unread = a;
  unread["runs"][0]["telemetry"] = {{"available", true}, {"throttled", nullptr}};
  unread["runs"][1]["telemetry"] = {{"available", false}, {"reason", "not NVIDIA"}};
  const CompareReport r = compareResults(unread, b, {});
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_EQ(r.warnings[0], "variant 'all_on_t8' in B: the GPU's clocks were held down (sw_power_cap)");
  EXPECT_TRUE(compareResults(a, a, {}).warnings.empty());
}

TEST(CompareResults, TwentyPercentSlowerIsARegression) {
  const json a = makeResults("abc", 1, 30, 1.0), b = makeResults("abc", 2, 30, 1.2);
  const CompareReport r = compareResults(a, b, {});
  EXPECT_TRUE(r.regression);
  for (const CompareRow& row : r.rows) {
    if (row.pass == "depth_prepass") continue;  // not scaled in B
    EXPECT_EQ(row.verdict, "slower") << row.variant << " " << row.pass;
    EXPECT_LT(row.p, 0.05);
    // Same 1.3 % bound as above on the ratio's sampling error.
    EXPECT_NEAR(row.ratio, 1.2, 1.2 * 0.013);
    EXPECT_LT(row.ciLow, row.ratio);
    EXPECT_GT(row.ciHigh, row.ratio);
    EXPECT_GT(row.ciLow, 1.05);
  }
  EXPECT_NEAR(r.geomeanRatio, 1.2, 1.2 * 0.013);
}

// The JUnit report: one test case per row, a failure per "slower" row (4 here: frame and shadows of
// both variants; depth_prepass is not scaled in B), none when the two draws match; well-formed XML
// with the counts in the suite's attributes.
TEST(CompareResults, JunitReportHasATestCasePerRowAndAFailurePerSlowdown) {
  const json a = makeResults("abc", 1, 30, 1.0), slow = makeResults("abc", 2, 30, 1.2),
             same = makeResults("abc", 2, 30, 1.0);
  CompareOptions all;
  all.gate = CompareGate::All;  // a failure per slower row, passes included
  const CompareReport r = compareResults(a, slow, all);
  const std::string xml = formatCompareJunit(r);
  EXPECT_EQ(testing::xmlProblem(xml), "") << xml;
  // The default gate (frames): only the two frame rows fail; the slower passes say so as output.
  const std::string frames = formatCompareJunit(compareResults(a, slow, {}));
  EXPECT_NE(frames.find("tests=\"6\" failures=\"2\""), std::string::npos) << frames;
  EXPECT_NE(frames.find("slower, not gated (gate frame"), std::string::npos) << frames;
  auto count = [&](const std::string& text, const std::string& what) {
    size_t n = 0;
    for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
  };
  size_t slower = 0;
  for (const CompareRow& row : r.rows) slower += row.verdict == "slower";
  EXPECT_EQ(slower, 4u);
  EXPECT_EQ(count(xml, "<testcase "), r.rows.size());
  EXPECT_EQ(count(xml, "<failure "), slower);
  EXPECT_NE(xml.find("tests=\"6\" failures=\"4\""), std::string::npos) << xml;
  const std::string fine = formatCompareJunit(compareResults(a, same, {}));
  EXPECT_EQ(testing::xmlProblem(fine), "");
  EXPECT_EQ(count(fine, "<failure "), 0u);
  EXPECT_NE(fine.find("failures=\"0\""), std::string::npos);
}

TEST(CompareResults, TwentyPercentFasterIsNotARegression) {
  const json a = makeResults("abc", 1, 30, 1.0), b = makeResults("abc", 2, 30, 0.8);
  const CompareReport r = compareResults(a, b, {});
  EXPECT_FALSE(r.regression);
  EXPECT_EQ(r.rows.front().verdict, "faster");
}

TEST(CompareResults, SlowdownBelowThresholdIsSame) {
  // +20 % with a 25 % threshold: significant, but within the threshold.
  const json a = makeResults("abc", 1, 30, 1.0), b = makeResults("abc", 2, 30, 1.2);
  CompareOptions o;
  o.thresholdPct = 25;
  const CompareReport r = compareResults(a, b, o);
  EXPECT_FALSE(r.regression);
  EXPECT_EQ(r.rows.front().verdict, "same");
  EXPECT_LT(r.rows.front().p, 0.05);
}

TEST(CompareResults, FewNoisySamplesAreTooNoisyAndWarn) {
  // 4 samples a side, CV 30 %, same center: not significant and below 5 samples.
  const json a = makeResults("abc", 1, 4, 1.0, 0.3), b = makeResults("abc", 2, 4, 1.0, 0.3);
  const CompareReport r = compareResults(a, b, {});
  EXPECT_EQ(r.rows.front().verdict, "too noisy");
  EXPECT_FALSE(r.regression);
  EXPECT_FALSE(r.warnings.empty());  // fewer than 20 samples
}

TEST(CompareResults, DifferentScenesAreRefusedNamingTheField) {
  const json a = makeResults("abc", 1, 30, 1.0), b = makeResults("def", 2, 30, 1.0);
  try {
    compareResults(a, b, {});
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("context.scene.sha256"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--force"), std::string::npos) << e.what();
  }
}

TEST(CompareResults, DifferentResolutionsAreRefused) {
  const json a = makeResults("abc", 1, 30, 1.0);
  json b = makeResults("abc", 2, 30, 1.0);
  b["context"]["config"]["resolution"] = {1280, 720};
  EXPECT_THROW(compareResults(a, b, {}), InputError);
}

// A results file from before a parameter existed (no "t_min" key) compares with a newer one whose
// runs carry that parameter's default; a non-default value is still a different config.
TEST(CompareResults, AParameterMissingFromAnOlderFileCountsAsItsDefault) {
  json a = makeResults("abc", 1, 30, 1.0), b = makeResults("abc", 2, 30, 1.0);
  json params = toJson(VariantParams{});
  b["context"]["config"]["variants"] = json::array({{{"name", "v"}, {"params", params}}});
  params.erase("t_min");
  a["context"]["config"]["variants"] = json::array({{{"name", "v"}, {"params", params}}});
  EXPECT_NO_THROW(compareResults(a, b, {}));
  b["context"]["config"]["variants"][0]["params"]["t_min"] = "scaled";
  try {
    compareResults(a, b, {});
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("context.config.variants"), std::string::npos) << e.what();
  }
}

TEST(CompareResults, ForceComparesDifferentScenesWithAWarning) {
  const json a = makeResults("abc", 1, 30, 1.0), b = makeResults("def", 2, 30, 1.2);
  CompareOptions o;
  o.force = true;
  const CompareReport r = compareResults(a, b, o);
  EXPECT_EQ(r.rows.size(), 6u);
  EXPECT_TRUE(r.regression);
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings.front().find("context.scene.sha256"), std::string::npos);
}

// A glTF at another path (another checkout) with the same content is one warning naming both
// paths; a built-in scene is its name, so another built-in is refused.
TEST(CompareResults, AGltfAtAnotherPathWarnsAndAnotherBuiltinIsRefused) {
  json a = makeResults("abc", 1, 30, 1.0), b = makeResults("abc", 2, 30, 1.0);
  a["context"]["config"]["scene"] = "/ci/1/scenes/cube.gltf";
  b["context"]["config"]["scene"] = "/ci/2/scenes/cube.gltf";
  const CompareReport r = compareResults(a, b, {});
  size_t moved = 0;
  for (const std::string& w : r.warnings)
    if (w.find("other paths") != std::string::npos) {
      ++moved;
      EXPECT_NE(w.find(R"(scene (A: "/ci/1/scenes/cube.gltf", B: "/ci/2/scenes/cube.gltf"))"), std::string::npos) << w;
    }
  EXPECT_EQ(moved, 1u);
  a["context"]["config"]["scene"] = "atrium";
  b["context"]["config"]["scene"] = "grazing";
  EXPECT_THROW(compareResults(a, b, {}), InputError);
}

// backend auto may choose another tracer on another device or driver: the variant is warned about.
TEST(CompareResults, AVariantTracedByAnotherRayTracerIsWarnedAbout) {
  json a = makeResults("abc", 1, 30, 1.0), b = makeResults("abc", 2, 30, 1.0);
  for (json* r : {&a, &b})
    for (json& run : (*r)["runs"]) run["backend_choice"] = {{"requested", "auto"}, {"ran", "compute"}};
  b["runs"][1]["backend_choice"]["ran"] = "pipeline";
  const CompareReport r = compareResults(a, b, {});
  EXPECT_EQ(r.a.tracer, "compute");
  EXPECT_EQ(r.b.tracer, "compute (1 run: no_opt_t8), pipeline (1 run: all_on_t8)");
  size_t warned = 0;
  for (const std::string& w : r.warnings)
    warned += w.find("variant 'all_on_t8': traced by compute in A, pipeline in B") == 0;
  EXPECT_EQ(warned, 1u);
}

TEST(CompareResults, UnmatchedAndFailedVariantsAreWarnedAndSkipped) {
  const json a = makeResults("abc", 1, 30, 1.0);
  json b = makeResults("abc", 2, 30, 1.0);
  b["runs"][0]["name"] = "renamed";
  b["runs"][1]["status"] = "error";
  const CompareReport r = compareResults(a, b, {});
  EXPECT_TRUE(r.rows.empty());
  EXPECT_TRUE(std::isnan(r.geomeanRatio));
  EXPECT_EQ(r.warnings.size(), 3u);  // only in A, skipped for status, only in B
}

TEST(CompareResults, NotAResultsFileIsInputError) {
  const json a = makeResults("abc", 1, 30, 1.0);
  EXPECT_THROW(compareResults(a, json{{"runs", json::array()}}, {}), InputError);
  json wrongVersion = a;
  wrongVersion["schema_version"] = 2;
  EXPECT_THROW(compareResults(a, wrongVersion, {}), InputError);
}

TEST(FormatCompare, MarkdownTableHasOneLinePerRowAndTheVerdict) {
  const json a = makeResults("abc", 1, 30, 1.0), b = makeResults("abc", 2, 30, 1.2);
  const CompareReport r = compareResults(a, b, {});
  const std::string text = formatCompare(r);
  EXPECT_NE(text.find("| variant | pass | A median (ms) | B median (ms) | B/A (Hodges-Lehmann) | 95 % CI of B/A"),
            std::string::npos)
      << text;
  size_t tableLines = 0;
  for (size_t pos = 0; (pos = text.find("\n| ", pos)) != std::string::npos; ++pos) ++tableLines;
  EXPECT_EQ(tableLines, r.rows.size() + 1);  // + header line (the separator starts with "|-")
  EXPECT_NE(text.find("| no_opt_t8 | frame |"), std::string::npos);
  EXPECT_NE(text.find("| slower |"), std::string::npos);
  EXPECT_NE(text.find("regression (a frame time slower beyond the threshold): yes"), std::string::npos);
  // Frame row first, then passes in frame order.
  EXPECT_LT(text.find("| no_opt_t8 | depth_prepass |"), text.find("| no_opt_t8 | shadows |"));
}

TEST(CompareToJson, CarriesRowsAndTheRegressionFlag) {
  const json a = makeResults("abc", 1, 30, 1.0), b = makeResults("abc", 2, 30, 1.2);
  const json j = toJson(compareResults(a, b, {}));
  EXPECT_TRUE(j["regression"].get<bool>());
  ASSERT_EQ(j["rows"].size(), 6u);
  for (const char* key : {"variant", "pass", "median_a", "median_b", "ratio", "ci_low", "ci_high", "p", "verdict"})
    EXPECT_TRUE(j["rows"][0].contains(key)) << key;
  EXPECT_EQ(j["rows"][0]["verdict"], "slower");
}

}  // namespace
}  // namespace hb

namespace hb {
namespace {

// A pass 20 % slower under an unchanged frame: only a gate that sees passes calls it a
// regression, and a pass under the floor on both sides never gates.
TEST(CompareGateUnit, APassSlowerUnderAnUnchangedFrameGatesOnlyWithPassesOrAll) {
  const json a = makeResults("abc", 1, 30, 1.0);
  json b = a;
  for (json& run : b["runs"])
    for (json& x : run["passes"]["shadows"]["samples"]) x = x.get<double>() * 1.2;
  for (json& run : b["runs"])
    run["passes"]["shadows"]["median"] = run["passes"]["shadows"]["median"].get<double>() * 1.2;
  CompareOptions o;
  EXPECT_FALSE(compareResults(a, b, o).regression);
  o.gate = CompareGate::All;
  const CompareReport all = compareResults(a, b, o);
  EXPECT_TRUE(all.regression);
  ASSERT_EQ(all.failures.size(), 2u);  // the shadows pass of both variants
  for (const CompareRow& row : all.rows) EXPECT_EQ(row.gates, row.pass == "shadows") << row.variant << row.pass;
  o.gate = CompareGate::Passes;
  EXPECT_TRUE(compareResults(a, b, o).regression);
  o.minMs = 1e6;  // every pass under the floor
  EXPECT_FALSE(compareResults(a, b, o).regression);
}

// B/A is the estimator of its interval: it lies inside it on every row, scaled or not.
TEST(CompareGateUnit, TheRatioLiesInsideItsOwnInterval) {
  for (double scale : {1.0, 1.03, 1.2}) {
    const CompareReport r = compareResults(makeResults("abc", 1, 30, 1.0), makeResults("abc", 2, 30, scale), {});
    for (const CompareRow& row : r.rows) {
      EXPECT_LE(row.ciLow, row.ratio) << scale << " " << row.variant << " " << row.pass;
      EXPECT_GE(row.ciHigh, row.ratio) << scale << " " << row.variant << " " << row.pass;
    }
  }
}

}  // namespace
}  // namespace hb
