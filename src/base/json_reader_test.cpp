// Strict JSON reading: numbers beyond a double or a float (what the config fuzzer found) and
// repeated keys.
#include "base/json_reader.h"

#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "base/input_error_of.h"

namespace hb::json_reader {
namespace {

// Found by fuzz_config (tests/fuzz/corpus/config/number-overflow.json): nlohmann::json throws
// out_of_range, not parse_error, for a number beyond a double, and it escaped as an internal error.
TEST(JsonText, ANumberBeyondADoubleIsMalformedJsonNamingTheFileAndTheNumber) {
  for (const char* number : {"1e999", "-1e3082160", "123456789e400"}) {
    const std::string text = std::string(R"({"frames": {"warmup": )") + number + "}}";
    EXPECT_EQ(inputErrorOf([&] { parseText(text, "x.json"); }),
              std::string("x.json: malformed JSON: number overflow parsing '") + number +
                  "'; write a number a double can hold (magnitude below 1.8e308)");
  }
  EXPECT_EQ(parseText(R"({"a": 1e308})", "x.json")["a"].get<double>(), 1e308);
}

// Found by fuzz_config (tests/fuzz/corpus/config/float-overflow.json): a light direction of
// [0.3, -1, 2.1e307] became a float with an inf, and NaN once normalised.
TEST(JsonReader, ANumberBeyondAFloatFailsWhereACastWouldMakeItInfinite) {
  const Where direction{"x.json", "lights[0].direction"};
  const Json big = Json::parse("[0.3, -1, 2.1e307]");
  EXPECT_EQ(inputErrorOf([&] { readFloats(big, direction, 3, "[x, y, z]"); }),
            "x.json: lights[0].direction[2]: 2.1e+307 is out of range for a float; give a "
            "magnitude below 3.4e38");
  EXPECT_EQ(readFloats(Json::parse("[3.4e38, -3.4e38, 0.5]"), direction, 3, "[x, y, z]"),
            (std::vector<float>{3.4e38f, -3.4e38f, 0.5f}));
  const Where intensity{"x.json", "lights[0].intensity"};
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(inputErrorOf([&] { readFloat(Json(1e39), intensity, 0.0, inf, false); }),
            "x.json: lights[0].intensity: 1e+39 is out of range for a float; give a magnitude "
            "below 3.4e38");
  EXPECT_EQ(readFloat(Json(20), intensity, 0.0, inf, false), 20.0f);
}

TEST(JsonText, AKeyGivenTwiceNamesTheObjectThatHoldsIt) {
  EXPECT_EQ(inputErrorOf([] { parseText(R"({"a": {"b": 1, "b": 2}})", "x.json"); }),
            "x.json: a: key \"b\" is given twice; keep one");
}

}  // namespace
}  // namespace hb::json_reader
