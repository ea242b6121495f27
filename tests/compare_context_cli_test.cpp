// What `hybridbench compare` says about what it compared, on committed results files (results/):
// a refusal names the first field that differs and both values; every format names each side's
// device and build (revision, driver, date); a forced comparison keeps its warnings in JUnit too;
// devices of different kinds (an H100 against llvmpipe) are named loudly; --json with another
// --format is refused; and a warning that holds for every variant is printed once, with its count.
#include <algorithm>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tool_process.h"

// A named namespace: the unity build puts this file beside others with helpers of the same names.
namespace compare_context_cli_test {

using namespace hb::testing;

const fs::path kResults = fs::path(HYBRIDBENCH_SOURCE_DIR) / "results";
// The thesis sweep on an H100 at 02f03e1, and the same config at 2b33675.
const std::string kThesis = (kResults / "h100/thesis/results.json.gz").string();
const std::string kThesis2b33675 = (kResults / "h100/thesis-2b33675/results.json.gz").string();
// The thesis config on lavapipe (a CPU device: its resolution lowered to 480x270).
const std::string kThesisLavapipe = (kResults / "lavapipe/thesis/results.json.gz").string();
// configs/scaling.json on the same H100: the same scene and resolution, other variants.
const std::string kScaling = (kResults / "h100/scaling/results.json.gz").string();
// The CI config at 02f03e1 on the H100 and on lavapipe (5 measured frames each).
const std::string kCiH100 = (kResults / "h100/ci/results.json.gz").string();
const std::string kCiLavapipe = (kResults / "lavapipe/ci/results.json.gz").string();

size_t occurrencesOf(const std::string& text, const std::string& needle) {
  size_t n = 0;
  for (size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) ++n;
  return n;
}

class CompareContext : public ToolTest {};

// The two configs share a long beginning ([{"name":"no optimisations","params":{"aa":"none",...),
// so a value cut at a fixed length never showed where they differ.
TEST_F(CompareContext, ARefusalNamesTheFirstFieldThatDiffersAndBothValues) {
  const RunResult r = run({"compare", kThesis, kScaling});
  EXPECT_EQ(r.exitCode, 2) << r.out << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(
      r.err.find(R"(context.config.variants[0].name differs (A: "no optimisations", B: "lights=10"); compare runs)"),
      std::string::npos)
      << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

TEST_F(CompareContext, EveryFormatNamesEachSidesDeviceRevisionDriverAndDate) {
  const json a = hb::testing::readJson(kThesis)["context"], b = hb::testing::readJson(kThesis2b33675)["context"];
  ASSERT_NE(a["tool"]["git"], b["tool"]["git"]);
  const RunResult md = run({"compare", kThesis, kThesis2b33675});
  EXPECT_EQ(md.exitCode, 0) << md.err;
  for (const json* side : {&a, &b}) {
    const std::string line = std::string(side == &a ? "A: " : "B: ") + (*side)["device"]["name"].get<std::string>() +
                             " (discrete GPU, driver " + (*side)["device"]["driver"].get<std::string>() +
                             // Runs of 02f03e1 and 2b33675 record no backend_choice: the device's is named.
                             ", ray tracing pipeline (the device's; the runs record no backend_choice), hybridbench " +
                             (*side)["tool"]["version"].get<std::string>() + " at revision " +
                             (*side)["tool"]["git"].get<std::string>() + ", swept " +
                             (*side)["host"]["date"].get<std::string>() + ")\n";
    EXPECT_NE(md.out.find(line), std::string::npos) << line << md.out;
  }

  const RunResult js = run({"compare", kThesis, kThesis2b33675, "--format", "json"});
  const json report = json::parse(js.out, nullptr, false);
  ASSERT_TRUE(report.is_object()) << js.out;
  EXPECT_EQ(report["schema_version"], 1);
  for (const auto& [key, context] : {std::pair<const char*, const json*>{"a", &a}, {"b", &b}}) {
    const json& side = report[key];
    EXPECT_EQ(side["device"], (*context)["device"]["name"]);
    EXPECT_EQ(side["device_type"], "discrete");
    EXPECT_EQ(side["driver"], (*context)["device"]["driver"]);
    EXPECT_EQ(side["revision"], (*context)["tool"]["git"]);
    EXPECT_EQ(side["version"], (*context)["tool"]["version"]);
    EXPECT_EQ(side["date"], (*context)["host"]["date"]);
  }
  EXPECT_EQ(report["devices_differ_in_kind"], false);

  const RunResult junit = run({"compare", kThesis, kThesis2b33675, "--format", "junit"});
  for (const auto& [key, context] : {std::pair<std::string, const json*>{"a", &a}, {"b", &b}}) {
    for (const auto& [name, value] : {std::pair<std::string, json>{"revision", (*context)["tool"]["git"]},
                                      {"driver", (*context)["device"]["driver"]},
                                      {"date", (*context)["host"]["date"]},
                                      {"device_type", "discrete"}}) {
      const std::string property =
          "<property name=\"" + key + "_" + name + "\" value=\"" + value.get<std::string>() + "\"/>";
      EXPECT_NE(junit.out.find(property), std::string::npos) << property << "\n" << junit.out;
    }
  }
}

// The thesis config on an H100 and on lavapipe, which lowers the resolution: forced, most rows are
// "not timed" (skipped), and nothing but the warnings says that the configs differ.
TEST_F(CompareContext, AForcedJunitComparisonCarriesItsWarnings) {
  const RunResult r = run({"compare", kThesis, kThesisLavapipe, "--force", "--format", "junit"});
  EXPECT_EQ(r.exitCode, 1) << r.err;
  const std::string what = "forced comparison: context.resolution differs (A: [1920,1080], B: [480,270])";
  EXPECT_NE(r.out.find("<property name=\"warning\" value=\"" + what + "\"/>"), std::string::npos) << r.out;
  // The suite's own output, after its cases, as CI systems show it beside them.
  const size_t systemErr = r.out.find("<system-err>");
  ASSERT_NE(systemErr, std::string::npos) << r.out;
  ASSERT_NE(r.out.rfind("</testcase>"), std::string::npos) << r.out;
  EXPECT_GT(systemErr, r.out.rfind("</testcase>")) << r.out;
  EXPECT_NE(r.out.find("warning: " + what + "\n", systemErr), std::string::npos) << r.out;
  // And the log of the job that wrote the XML to a file says it too.
  EXPECT_NE(r.err.find("warning: " + what + "\n"), std::string::npos) << r.err;
}

TEST_F(CompareContext, DevicesOfDifferentKindsAreNamedLoudly) {
  const std::string warning =
      "the devices differ in kind: A is a discrete GPU (NVIDIA H100 80GB HBM3), B is a CPU device "
      "(llvmpipe (LLVM 15.0.6, 256 bits)); B/A measures the two devices, not a change of build";
  const RunResult md = run({"compare", kCiH100, kCiLavapipe});
  EXPECT_EQ(md.exitCode, 1) << md.err;  // llvmpipe is slower: the gate still says so
  // Right under the two sides, before the table, and beside the verdict.
  const size_t loud = md.out.find("WARNING: " + warning + "\n");
  ASSERT_NE(loud, std::string::npos) << md.out;
  EXPECT_LT(loud, md.out.find("| variant |")) << md.out;
  EXPECT_NE(md.out.find("regression (a frame time slower beyond the threshold): yes (between devices of different "
                        "kinds: see the warning above)"),
            std::string::npos)
      << md.out;

  const RunResult js = run({"compare", kCiH100, kCiLavapipe, "--json"});
  const json report = json::parse(js.out, nullptr, false);
  ASSERT_TRUE(report.is_object()) << js.out;
  EXPECT_EQ(report["devices_differ_in_kind"], true);
  EXPECT_EQ(report["warnings"][0], warning);
  EXPECT_EQ(report["a"]["device_type"], "discrete");
  EXPECT_EQ(report["b"]["device_type"], "cpu");
  EXPECT_NE(js.err.find("warning: " + warning), std::string::npos) << js.err;

  // Two GPUs of one kind: no such warning.
  const RunResult same = run({"compare", kThesis, kThesis2b33675});
  EXPECT_EQ(same.out.find("differ in kind"), std::string::npos) << same.out;
}

TEST_F(CompareContext, JsonWithAnotherFormatIsRefused) {
  const RunResult r = run({"compare", kThesis, kThesis2b33675, "--format", "junit", "--json"});
  EXPECT_EQ(r.exitCode, 2) << r.out << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("--json and --format junit contradict each other"), std::string::npos) << r.err;
  // The two that agree are fine.
  const RunResult same = run({"compare", kThesis, kThesis2b33675, "--format", "json", "--json"});
  EXPECT_EQ(same.exitCode, 0) << same.err;
  EXPECT_TRUE(json::parse(same.out, nullptr, false).is_object()) << same.out;
}

// Both CI runs measured 5 frames in each of their 9 variants: one warning says so, with the count.
TEST_F(CompareContext, AWarningForEveryVariantIsPrintedOnceWithItsCount) {
  const size_t variants = hb::testing::readJson(kCiH100)["runs"].size();
  ASSERT_GT(variants, 1u);
  const RunResult r = run({"compare", kCiH100, kCiLavapipe});
  EXPECT_EQ(occurrencesOf(r.out, "frame samples"), 1u) << r.out;
  EXPECT_NE(r.out.find("- " + std::to_string(variants) +
                       " variants ('no optimisations', ...): only 5 (A) and 5 (B) frame samples; fewer than 20"),
            std::string::npos)
      << r.out;
}

}  // namespace compare_context_cli_test
