// The roofline's arithmetic on hand-made work and peaks (report/roofline.h): achieved = work / time,
// fraction = achieved / peak, the bound is the unit closest to its peak, a unit without a peak has
// no fraction, and an entry without a time has no roofline. The table's share of its ceiling: the
// launch where the empty dispatch's time is the larger share, and with measured ceilings a unit no
// device peak counts rated against the ceiling run of the same pass, primary and aa.
#include "report/roofline.h"

#include <gtest/gtest.h>

namespace hb {
namespace {

TEST(Roofline, TheBoundIsTheUnitClosestToItsPeak) {
  // 2e6 bytes and 1e3 rays in 1 ms: 2e9 B/s against 4e9 (0.5), 1e6 rays/s against 1e9 (0.001);
  // in either order the bytes bound the pass.
  const WorkItem rays{"rays", 1e3, "counted: rays"}, bytes{"bytes", 2e6, "derived: bytes"};
  for (const std::vector<WorkItem>& items : {std::vector<WorkItem>{rays, bytes}, std::vector<WorkItem>{bytes, rays}}) {
    const nlohmann::json r = rooflineJson({{"pass", items}}, {{"pass", 1.0}}, {{"bytes", 4e9}, {"rays", 1e9}});
    ASSERT_TRUE(r.contains("pass"));
    const nlohmann::json& e = r["pass"];
    EXPECT_EQ(e["bound"], "bytes");
    EXPECT_EQ(e["unit"], "bytes");
    EXPECT_EQ(e["source"], "derived: bytes");
    EXPECT_DOUBLE_EQ(e["achieved_per_s"].get<double>(), 2e9);
    EXPECT_DOUBLE_EQ(e["fraction"].get<double>(), 0.5);
    ASSERT_EQ(e["loads"].size(), 2u);
    for (const nlohmann::json& load : e["loads"])
      EXPECT_DOUBLE_EQ(load["fraction"].get<double>(), load["unit"] == "rays" ? 1e6 / 1e9 : 0.5);
  }
}

TEST(Roofline, AUnitWithoutAPeakHasNoFractionAndAnUntimedEntryNoRoofline) {
  const std::vector<PassWork> works = {{"timed", {{"fragments", 5e5, "derived: one per pixel"}}},
                                       {"untimed", {{"bytes", 1.0, "derived: one byte"}}}};
  const nlohmann::json r = rooflineJson(works, {{"timed", 2.0}}, {{"bytes", 1e9}});
  EXPECT_FALSE(r.contains("untimed"));
  const nlohmann::json& e = r["timed"];
  EXPECT_EQ(e["bound"], "fragments");  // the only unit, though it has no peak
  EXPECT_TRUE(e["fraction"].is_null());
  EXPECT_DOUBLE_EQ(e["peak_per_s"].get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(e["achieved_per_s"].get<double>(), 5e5 / 2e-3);
}

// A results file of one run whose two entries carry the rooflineJson of the given work and times,
// on a device whose empty dispatch takes 0.005 ms.
nlohmann::json resultsOf(const std::string& device, const std::vector<PassWork>& works,
                         const std::map<std::string, double>& ms, nlohmann::json params) {
  nlohmann::json run = {{"name", "run"}, {"status", "ok"}, {"params", std::move(params)}};
  run["roofline"] = rooflineJson(works, ms, {{"bytes", 1e12}});
  nlohmann::json results = {{"runs", nlohmann::json::array({run})}};
  nlohmann::json empty = {{"ms", {{"median", 0.005}}}, {"per_s", 200.0}};
  results["context"]["device"]["name"] = device;
  results["context"]["device"]["peaks"]["figures"]["dispatch_empty"] = empty;
  return results;
}

// The table row of `entry` (its cells from "| run | entry |" to the line's end).
std::string rowOf(const std::string& md, const std::string& entry) {
  const size_t at = md.find("| run | " + entry + " |");
  return at == std::string::npos ? "" : md.substr(at, md.find('\n', at) - at);
}

TEST(Roofline, AShortPassIsBoundByTheLaunchAndALoopByItsCeilingRun) {
  // "short": 1e6 bytes in 0.01 ms = 1e11 B/s, 10 % of 1e12; the empty dispatch's 0.005 ms is 50 % of
  // its time, so the launch sets its share. "loop": 3e9 steps in 1 ms = 3e12 a second, no device peak.
  const std::vector<PassWork> works = {{"short", {{"bytes", 1e6, "derived: bytes"}}},
                                       {"loop", {{"tile_loop_steps", 3e9, "counted: steps"}}}};
  const nlohmann::json params = {{"primary", "3dr-binned"}, {"aa", "none"}};
  const nlohmann::json results = resultsOf("GPU", works, {{"short", 0.01}, {"loop", 1.0}}, params);
  // Without ceilings the table has no share column (earlier studies' tables keep theirs).
  const std::string plain = rooflineMarkdown(results);
  EXPECT_NE(rowOf(plain, "short").find("| 10.0 % | derived: bytes |"), std::string::npos) << plain;
  EXPECT_EQ(plain.find("Share of its ceiling"), std::string::npos) << plain;

  // The ceiling run did the loop's steps at 4e12 a second (4e9 in 1 ms): 75 %.
  const nlohmann::json ceilingRun =
      resultsOf("GPU", {{"loop", {{"tile_loop_steps", 4e9, "counted: steps"}}}}, {{"loop", 1.0}}, params);
  const MeasuredCeilings ceilings = measuredCeilings(ceilingRun, "ceiling.json");
  ASSERT_EQ(ceilings.rates.size(), 1u);
  const std::string rated = rooflineMarkdown(results, &ceilings);
  EXPECT_NE(rowOf(rated, "short").find("| 10.0 % | 50.0 % (launch) |"), std::string::npos) << rated;
  EXPECT_NE(rowOf(rated, "loop").find("| tile_loop_steps |"), std::string::npos) << rated;
  EXPECT_NE(rowOf(rated, "loop").find("| 75.0 % | 75.0 % (tile_loop_steps) |"), std::string::npos) << rated;
  EXPECT_NE(rated.find("Measured ceilings: ceiling.json"), std::string::npos);

  // Another aa (or primary) is another loop: its ceiling does not rate this run.
  const nlohmann::json msaa = resultsOf("GPU", {{"loop", {{"tile_loop_steps", 4e9, "counted: steps"}}}},
                                        {{"loop", 1.0}}, {{"primary", "3dr-binned"}, {"aa", "msaa16"}});
  const MeasuredCeilings other = measuredCeilings(msaa, "msaa.json");
  EXPECT_NE(rowOf(rooflineMarkdown(results, &other), "loop").find("| — | — |"), std::string::npos);
  EXPECT_EQ(ceilingMatches(results, other), 0u);  // `tables --ceiling` refuses such files
  EXPECT_EQ(ceilingMatches(results, ceilings), 1u);

  // A unit a device peak rates is never taken from a ceiling run.
  const nlohmann::json bytesOnly = resultsOf("GPU", works, {{"short", 0.001}, {"loop", 1.0}}, params);
  EXPECT_EQ(measuredCeilings(bytesOnly, "b.json").rates.count(ceilingKey("short", "bytes", params)), 0u);
}

}  // namespace
}  // namespace hb
