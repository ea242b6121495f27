// `sweep --shard K/N` and `hybridbench merge` (issue #35, docs/fleet.md): a config split into
// parts that run at once in separate processes, as on the machines of a fleet, then merged, gives
// what one sweep of the whole config gives. End to end, the built tool on the device present
// (lavapipe on CI).
#include <algorithm>
#include <filesystem>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tool_process.h"

namespace {

using namespace hb::testing;

// Five variants at 64x36 (one at 96x54), one measured frame: three of them share one no-culling
// reference, one renders its own at its resolution, one a supersampled reference.
const fs::path kShardFixture = fs::path(HYBRIDBENCH_SOURCE_DIR) / "tests/fixtures/sweep-shard.json";

// What a run's record holds that is a time, or computed from one: left out of the comparison.
// roofline's achieved rates and fractions divide by times; its work (counted or derived) is kept.
// telemetry: the clocks, power and temperature read around the frames (gpu/telemetry.h), measured too.
const std::set<std::string> kShardTimedKeys = {
    "frame_ms",   "passes",   "frame_minus_passes_ms", "warmup_s", "raybench",
    "analysis_s", "build_ms", "warmup_frames",         "roofline", "telemetry"};

// Every field of a and b but the timed ones, as "path: a -> b" lines.
void shardDiffUntimed(const json& a, const json& b, const std::string& path, std::vector<std::string>& out) {
  if (a.is_object() && b.is_object()) {
    std::set<std::string> keys;
    for (const auto& [k, v] : a.items()) keys.insert(k);
    for (const auto& [k, v] : b.items()) keys.insert(k);
    for (const std::string& k : keys) {
      if (kShardTimedKeys.count(k)) continue;
      if (!a.contains(k) || !b.contains(k))
        out.push_back(path + "/" + k + ": only in " + (a.contains(k) ? "A" : "B"));
      else
        shardDiffUntimed(a[k], b[k], path + "/" + k, out);
    }
  } else if (a.is_array() && b.is_array() && a.size() == b.size()) {
    for (size_t i = 0; i < a.size(); ++i) shardDiffUntimed(a[i], b[i], path + "[" + std::to_string(i) + "]", out);
  } else if (a != b) {
    out.push_back(path + ": " + a.dump().substr(0, 80) + " -> " + b.dump().substr(0, 80));
  }
}

// The work every roofline entry counted or derived (the untimed half of the roofline).
json shardRooflineWork(const json& run) {
  json work = json::object();
  if (!run.contains("roofline") || !run["roofline"].is_object()) return work;
  for (const auto& [entry, r] : run["roofline"].items()) {
    if (!r.is_object() || !r.contains("loads")) continue;
    for (const json& load : r["loads"])
      work[entry].push_back(load.is_object() ? json::array({load.value("unit", json()), load.value("work", json())})
                                             : load);
  }
  return work;
}

std::vector<std::string> shardRunNames(const json& results) {
  std::vector<std::string> names;
  for (const json& run : results["runs"]) names.push_back(run.value("name", ""));
  return names;
}

size_t shardLineCount(const std::string& s) { return size_t(std::count(s.begin(), s.end(), '\n')); }

class SweepShard : public ToolTest {
 protected:
  struct Child {
    pid_t pid;
    int n;  // its stdout and stderr files (ToolTest numbers them)
  };
  Child launch(const std::vector<std::string>& args) { return {start(args), children_}; }
  // ToolTest::wait reads the latest child's files; several ran at once, so each reads its own.
  RunResult finish(const Child& c) {
    RunResult r = wait(c.pid);
    r.out = readFile(dir / (".stdout" + std::to_string(c.n)));
    r.err = readFile(dir / (".stderr" + std::to_string(c.n)));
    EXPECT_EQ(r.err.find("validation:"), std::string::npos) << r.err;
    return r;
  }
  std::vector<std::string> sweepArgs(const fs::path& out) const {
    return {"sweep", kShardFixture.string(), "--out", out.string()};
  }
};

TEST_F(SweepShard, ThreePartsAtOnceMergeIntoWhatOneSweepGivesAndMergeRefusesPartsThatDoNotBelong) {
  const fs::path whole = dir / "whole", merged = dir / "merged";
  std::vector<fs::path> parts;
  for (int k = 0; k < 3; ++k) parts.push_back(dir / ("part" + std::to_string(k)));
  // The whole sweep, its three parts and an empty part (5 variants, 6 parts) at once.
  std::vector<Child> children{launch(sweepArgs(whole))};
  for (int k = 0; k < 3; ++k) {
    std::vector<std::string> args = sweepArgs(parts[k]);
    args.insert(args.end(), {"--shard", std::to_string(k) + "/3"});
    children.push_back(launch(args));
  }
  std::vector<std::string> emptyArgs = sweepArgs(dir / "empty");
  emptyArgs.insert(emptyArgs.end(), {"--shard", "5/6"});
  children.push_back(launch(emptyArgs));
  for (const Child& c : children) {
    const RunResult r = finish(c);
    ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  }

  // The parts: every variant in exactly one, as context.shard says, balanced by cost (the
  // supersampled reference costs 4 of the others' 1, the 96x54 variant 2.25: three parts of
  // {ssaa}, {96x54}, {the three 64x36 at 1 each}).
  const json config = readJson(kShardFixture);
  std::vector<std::string> configNames;
  for (const json& v : config["variants"]) configNames.push_back(v["name"]);
  std::multiset<std::string> seen;
  std::vector<std::vector<std::string>> partNames;
  for (int k = 0; k < 3; ++k) {
    const json r = readJson(parts[k] / "results.json");
    ASSERT_FALSE(r.is_discarded()) << parts[k];
    const json& shard = r["context"]["shard"];
    EXPECT_EQ(shard.value("index", -1), k);
    EXPECT_EQ(shard.value("count", -1), 3);
    EXPECT_EQ(shard["variants"].get<std::vector<std::string>>(), shardRunNames(r));
    partNames.push_back(shardRunNames(r));
    for (const std::string& n : shardRunNames(r)) seen.insert(n);
  }
  EXPECT_EQ(seen, std::multiset<std::string>(configNames.begin(), configNames.end()));
  EXPECT_EQ(partNames[0], std::vector<std::string>{"supersampled reference"});
  EXPECT_EQ(partNames[1], std::vector<std::string>{"16x16 at 96x54"});
  EXPECT_EQ(partNames[2], (std::vector<std::string>{"no culling", "improved culling", "naive culling"}));
  const json empty = readJson(dir / "empty" / "results.json");
  ASSERT_FALSE(empty.is_discarded());
  EXPECT_TRUE(empty["runs"].empty());
  EXPECT_EQ(empty["context"]["shard"].value("count", 0), 6);
  EXPECT_TRUE(empty["context"].contains("device"));

  // Merged in another order than the parts' (the merge orders runs as the config does).
  const RunResult m = run({"merge", parts[2].string(), parts[0].string(), parts[1].string(), "--out", merged.string()});
  ASSERT_EQ(m.exitCode, 0) << m.out << m.err;
  const json a = readJson(whole / "results.json"), b = readJson(merged / "results.json");
  ASSERT_FALSE(a.is_discarded());
  ASSERT_FALSE(b.is_discarded());
  ASSERT_EQ(shardRunNames(a), configNames);
  ASSERT_EQ(shardRunNames(b), configNames);
  EXPECT_FALSE(b["context"].contains("shard"));
  ASSERT_EQ(b["context"]["merged_from"].size(), 3u);
  EXPECT_EQ(b["context"]["merged_from"][0]["shard"].value("index", -1), 2);
  // Counts and accuracy equal exactly, not within a tolerance: the same binary renders the same
  // frames on the same device, and a variant's reference is keyed by its own parameters
  // (referenceParams), never by which variants ran before it in its process.
  for (size_t i = 0; i < a["runs"].size(); ++i) {
    const json &ra = a["runs"][i], &rb = b["runs"][i];
    ASSERT_EQ(ra.value("status", ""), "ok") << ra.dump().substr(0, 400);
    EXPECT_TRUE(ra.contains("rays") && ra.contains("accuracy")) << ra.value("name", "");
    std::vector<std::string> differences;
    shardDiffUntimed(ra, rb, ra.value("name", ""), differences);
    EXPECT_TRUE(differences.empty()) << ::testing::PrintToString(differences);
    EXPECT_EQ(shardRooflineWork(ra), shardRooflineWork(rb)) << ra.value("name", "");
  }
  // Every image, byte for byte (the PNGs' text chunks name the same build).
  size_t images = 0;
  for (const auto& e : fs::recursive_directory_iterator(whole)) {
    if (e.path().extension() != ".png") continue;
    ++images;
    const fs::path other = merged / fs::relative(e.path(), whole);
    EXPECT_TRUE(fs::exists(other) && readFile(e.path()) == readFile(other)) << other;
  }
  EXPECT_GE(images, 5u * 3u);  // every variant writes at least colour, depth and FLIP error
  // The tables regenerate from the merged file, and what merge wrote is what `tables` prints.
  const RunResult tables = run({"tables", (merged / "results.json").string()});
  ASSERT_EQ(tables.exitCode, 0) << tables.err;
  EXPECT_EQ(tables.out, readFile(merged / "tables.md") + "\n" + readFile(merged / "accuracy.md"));
  // The report page, where sweep writes one (writeSweepOutputs), is written by merge too.
  EXPECT_EQ(fs::exists(merged / "report.html"), fs::exists(whole / "report.html"));

  // What merge refuses, each with one line and exit 2, writing nothing.
  auto edited = [&](const std::string& name, const std::function<void(json&)>& edit) {
    const fs::path copy = dir / name;
    fs::copy(parts[1], copy, fs::copy_options::recursive);
    json r = readJson(copy / "results.json");
    edit(r);
    writeFile(copy / "results.json", r.dump());
    return copy;
  };
  auto refused = [&](const std::vector<std::string>& args, const std::string& names) {
    static int calls = 0;  // a fresh --out each, so that one wrongly accepted merge fails only its own case
    const fs::path out = dir / ("refused" + std::to_string(++calls));
    std::vector<std::string> all = {"merge"};
    all.insert(all.end(), args.begin(), args.end());
    all.insert(all.end(), {"--out", out.string()});
    const RunResult r = run(all);
    EXPECT_EQ(r.exitCode, 2) << r.out << r.err;
    EXPECT_EQ(shardLineCount(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find(names), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out / "results.json")) << r.err;
  };
  const fs::path otherRevision = edited("revision", [](json& r) { r["context"]["tool"]["git"] = "0000000"; });
  refused({parts[0].string(), otherRevision.string(), parts[2].string()}, "the revision differs");
  const fs::path otherConfig = edited("config", [](json& r) { r["context"]["config"]["frames"]["measured"] = 2; });
  refused({parts[0].string(), otherConfig.string(), parts[2].string()}, "the config differs (at /frames/measured");
  const fs::path otherScene = edited("scene", [](json& r) { r["context"]["scene"]["sha256"] = "0"; });
  refused({parts[0].string(), otherScene.string(), parts[2].string()}, "the scene hash differs");
  const fs::path otherDevice = edited("device", [](json& r) { r["context"]["device"]["name"] = "Other GPU"; });
  refused({parts[0].string(), otherDevice.string(), parts[2].string()}, "the device name differs");
  refused({parts[0].string(), parts[2].string()}, "missing part(s) 1/3");
  refused({parts[0].string(), parts[1].string(), parts[2].string(), (dir / "whole").string()}, "is in both");
  refused({parts[0].string(), (dir / "nowhere").string()}, "nowhere");
  // An --out that holds results is refused (without --force), and the earlier results stay.
  const std::string before = readFile(merged / "results.json");
  const RunResult again =
      run({"merge", parts[0].string(), parts[1].string(), parts[2].string(), "--out", merged.string()});
  EXPECT_EQ(again.exitCode, 2) << again.err;
  EXPECT_NE(again.err.find("already holds results"), std::string::npos) << again.err;
  EXPECT_EQ(readFile(merged / "results.json"), before);

  // --force: parts from devices of different names merge, and each run records its device.
  const fs::path mixed = dir / "mixed";
  const RunResult f =
      run({"merge", parts[0].string(), otherDevice.string(), parts[2].string(), "--out", mixed.string(), "--force"});
  ASSERT_EQ(f.exitCode, 0) << f.out << f.err;
  EXPECT_NE(f.err.find("different devices"), std::string::npos) << f.err;
  const json mj = readJson(mixed / "results.json");
  ASSERT_EQ(shardRunNames(mj), configNames);
  const std::string own = a["context"]["device"].value("name", "");
  for (const json& run : mj["runs"])
    EXPECT_EQ(run.contains("device") && run["device"].is_object() ? run["device"].value("name", "") : "(none)",
              run.value("name", "") == "16x16 at 96x54" ? "Other GPU" : own)
        << run.value("name", "");
  EXPECT_EQ(mj["context"]["mixed_devices"].size(), 2u);
}

TEST_F(SweepShard, DryRunPrintsThePartsVariantsAndEveryPartsEstimateAndBadShardsAreOneLine) {
  const RunResult r = run({"sweep", kShardFixture.string(), "--shard", "2/3", "--dry-run"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("shard 2/3: 3 of 5 variants"), std::string::npos) << r.out;
  for (const char* part : {"part 0/3: 1 variant", "part 1/3: 1 variant", "part 2/3: 3 variants"})
    EXPECT_NE(r.out.find(part), std::string::npos) << part << "\n" << r.out;
  EXPECT_NE(r.out.find("   1. no culling"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("supersampled reference:"), std::string::npos) << r.out;  // part 0's
  for (const char* bad : {"3/3", "1/0", "x", "+1/2"}) {
    const RunResult b = run({"sweep", kShardFixture.string(), "--shard", bad, "--dry-run"});
    EXPECT_EQ(b.exitCode, 2) << bad << b.out;
    EXPECT_EQ(shardLineCount(b.err), 1u) << b.err;
    EXPECT_NE(b.err.find("--shard"), std::string::npos) << b.err;
  }
}

}  // namespace
