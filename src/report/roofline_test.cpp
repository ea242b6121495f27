// The roofline's arithmetic on hand-made work and peaks (report/roofline.h): achieved = work / time,
// fraction = achieved / peak, the bound is the unit closest to its peak, a unit without a peak has
// no fraction, and an entry without a time has no roofline.
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

}  // namespace
}  // namespace hb
