#include "app/sweep_shard.h"

#include <algorithm>

#include <gtest/gtest.h>

#include "base/errors.h"

namespace hb {
namespace {

TEST(ShardPlan, ParsesKOfNCountedFromZeroAndRefusesEverythingElse) {
  EXPECT_EQ(parseShard("0/1").index, 0u);
  EXPECT_EQ(parseShard("2/3").index, 2u);
  EXPECT_EQ(parseShard("2/3").count, 3u);
  for (const char* bad : {"3/3", "1/0", "-1/3", "1", "a/3", "1/3/4", "/3", "1/", "+1/3", "1/10000000", ""})
    EXPECT_THROW(parseShard(bad), InputError) << bad;
  try {
    parseShard("3/3");
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("from 0 to 2"), std::string::npos) << e.what();
  }
}

TEST(ShardPlan, LongestFirstPutsEveryVariantInExactlyOnePartInConfigOrder) {
  // Costs 5,4,3,3,2,1 into 3 parts: LPT gives {5,1}=6, {4,2}=6, {3,3}=6.
  const ShardPlan plan = partitionByCost({5, 4, 3, 3, 2, 1}, 3);
  ASSERT_EQ(plan.parts.size(), 3u);
  EXPECT_EQ(plan.parts[0], (std::vector<size_t>{0, 5}));
  EXPECT_EQ(plan.parts[1], (std::vector<size_t>{1, 4}));
  EXPECT_EQ(plan.parts[2], (std::vector<size_t>{2, 3}));
  EXPECT_EQ(plan.partCosts, (std::vector<double>{6, 6, 6}));
  // Equal costs: ties by config order, round robin over the parts.
  const ShardPlan even = partitionByCost({1, 1, 1, 1}, 2);
  EXPECT_EQ(even.parts[0], (std::vector<size_t>{0, 2}));
  EXPECT_EQ(even.parts[1], (std::vector<size_t>{1, 3}));
  // More parts than variants: the rest are empty.
  const ShardPlan sparse = partitionByCost({2, 1}, 4);
  EXPECT_EQ(sparse.parts[0], (std::vector<size_t>{0}));
  EXPECT_EQ(sparse.parts[1], (std::vector<size_t>{1}));
  EXPECT_TRUE(sparse.parts[2].empty());
  EXPECT_TRUE(sparse.parts[3].empty());
}

TEST(ShardPlan, CostGrowsWithPixelsLightsAndEffects) {
  VariantParams p;
  p.resolution = {100, 10};
  p.lightCount = 9;
  const double base = variantCost(p, nlohmann::json::object(), 0);
  EXPECT_EQ(base, 1000.0 * 10.0);
  EXPECT_EQ(variantCost(p, {{"shadows", true}}, 0), base);  // shadows are the lights' term
  EXPECT_EQ(variantCost(p, {{"ambient_occlusion", {{"method", "ldm"}}}}, 0), base * kEffectCostWeight);
  p.effects = {{"ambient_occlusion", false}};  // the variant's layer turns the config's off
  EXPECT_EQ(variantCost(p, {{"ambient_occlusion", true}}, 0), base);
  p.effects = nullptr;
  p.lightCount.reset();
  EXPECT_EQ(variantCost(p, nlohmann::json::object(), 19), 1000.0 * 20.0);  // the scene's lights
  p.referenceSsaa = 4;
  EXPECT_EQ(variantCost(p, nlohmann::json::object(), 19), 4 * 1000.0 * 20.0);
}

}  // namespace
}  // namespace hb
