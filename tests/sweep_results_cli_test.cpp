// `hybridbench sweep` end to end, what it writes: the built tool (HYBRIDBENCH_BINARY) sweeps the tiny
// config tests/fixtures/sweep-tiny.json as a child process with HYBRIDBENCH_VALIDATION=1 (no
// "validation:" line may be printed), and results.json, results.csv and tables.md are held to
// docs/results-format.md: every finished variant complete, a variant the renderer refuses recorded
// as an error while the sweep goes on, and the ambient occlusion variants' errors and table. Each
// sweep takes a few seconds on lavapipe (2 cores).
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "sweep_cli.h"

namespace hb::sweep_test {
namespace {

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

  // --ceiling: only with the roofline table, only from the same device, and only a file whose runs
  // measured a rate no device peak counts (this sweep's thesis frames have none); one line, exit 2.
  const RunResult noFormat = run({"tables", file, "--ceiling", file});
  EXPECT_EQ(noFormat.exitCode, 2);
  EXPECT_NE(noFormat.err.find("--format roofline"), std::string::npos) << noFormat.err;
  const RunResult otherDevice =
      run({"tables", file, "--format", "roofline", "--ceiling", (out / "other.json").string()});
  EXPECT_EQ(otherDevice.exitCode, 2);
  EXPECT_NE(otherDevice.err.find("another GPU"), std::string::npos) << otherDevice.err;
  const RunResult noRates = run({"tables", file, "--format", "roofline", "--ceiling", file});
  EXPECT_EQ(noRates.exitCode, 2);
  EXPECT_NE(noRates.err.find("configs/ceilings"), std::string::npos) << noRates.err;
  // A field of the wrong type (a roofline entry's loads that are numbers, not objects) is the file's
  // fault: one line naming the file, exit 2, nothing printed (it was exit 3, an internal error).
  nlohmann::json mistyped = results;
  bool edited = false;
  for (nlohmann::json& entry : mistyped["runs"])
    if (!edited && entry.contains("roofline") && !entry["roofline"].empty()) {
      entry["roofline"].begin()->operator[]("loads") = nlohmann::json::array({7});
      edited = true;
    }
  ASSERT_TRUE(edited) << "no run of the tiny sweep has a roofline entry";
  std::ofstream(out / "mistyped.json") << mistyped.dump();
  const RunResult wrongType = run({"tables", (out / "mistyped.json").string(), "--format", "roofline"});
  EXPECT_EQ(wrongType.exitCode, 2) << wrongType.err;
  EXPECT_NE(wrongType.err.find("mistyped.json: a field has the wrong type"), std::string::npos) << wrongType.err;
  EXPECT_EQ(wrongType.out, "");
  for (const RunResult* line : {&noFormat, &otherDevice, &noRates, &wrongType})
    EXPECT_EQ(std::count(line->err.begin(), line->err.end(), '\n'), 1) << line->err;
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

}  // namespace
}  // namespace hb::sweep_test
