#include "base/json_diff.h"

#include <gtest/gtest.h>

namespace hb {
namespace {

using nlohmann::json;

TEST(JsonDiff, EqualValuesHaveNoDifferenceAndNumbersCompareByValue) {
  EXPECT_FALSE(firstDifference(json::parse(R"({"a": [1, {"b": 2}]})"), json::parse(R"({"a": [1.0, {"b": 2}]})")));
}

TEST(JsonDiff, NamesTheDeepestFieldThatDiffersPastACommonPrefix) {
  // The two share a long common beginning: the difference is inside the first variant's params.
  const json a = json::parse(R"({"variants": [{"name": "no optimisations", "params": {"aa": "none", "tile": 16}}]})");
  json b = a;
  b["variants"][0]["params"]["tile"] = 32;
  const auto d = firstDifference(a, b, "context.config");
  ASSERT_TRUE(d);
  EXPECT_EQ(d->path, "context.config.variants[0].params.tile");
  EXPECT_EQ(describeDifference(*d, "A", "B"), "context.config.variants[0].params.tile differs (A: 16, B: 32)");
}

TEST(JsonDiff, AKeyOrElementOnOneSideIsAbsentOnTheOther) {
  const auto key = firstDifference(json{{"a", 1}}, json{{"a", 1}, {"b", "x"}});
  ASSERT_TRUE(key);
  EXPECT_EQ(describeDifference(*key, "was", "now"), "b differs (was: (absent), now: \"x\")");
  const auto element = firstDifference(json::parse(R"([{"n": 1}, {"n": 2}])"), json::parse(R"([{"n": 1}])"), "v");
  ASSERT_TRUE(element);
  EXPECT_EQ(describeDifference(*element, "A", "B"), "v[1] differs (A: {\"n\":2}, B: (absent))");
}

TEST(JsonDiff, AnArrayOfNumbersDiffersAsAWhole) {
  const auto d = firstDifference(json{{"resolution", {1920, 1080}}}, json{{"resolution", {480, 270}}}, "context");
  ASSERT_TRUE(d);
  EXPECT_EQ(describeDifference(*d, "A", "B"), "context.resolution differs (A: [1920,1080], B: [480,270])");
}

TEST(JsonDiff, DifferentKindsDifferAtTheirPathAndLongValuesAreCut) {
  const auto d = firstDifference(json{{"x", std::string(100, 'a')}}, json{{"x", 5}});
  ASSERT_TRUE(d);
  EXPECT_EQ(d->path, "x");
  EXPECT_EQ(shortJson(d->a).size(), 60u);
  EXPECT_EQ(shortJson(d->a).substr(57), "...");
  EXPECT_EQ(describeDifference(*firstDifference(json(1), json("1")), "A", "B"), "the value differs (A: 1, B: \"1\")");
}

}  // namespace
}  // namespace hb
