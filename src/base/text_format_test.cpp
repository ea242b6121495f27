#include "base/text_format.h"

#include <gtest/gtest.h>

namespace hb {
namespace {

TEST(TextFormat, CountOfSaysOneLightAndTenLights) {
  EXPECT_EQ(countOf(1, "light"), "1 light");
  EXPECT_EQ(countOf(0, "light"), "0 lights");
  EXPECT_EQ(countOf(10, "light"), "10 lights");
  EXPECT_EQ(countOf(2, "variant"), "2 variants");
}

// A ray efficiency of oracle / traced just above 1 is a culler that missed rays: printed as
// "1.000" it read as perfect (the atrium's 659,121 / 659,120 = 1.0000015).
TEST(TextFormat, FormatNear1ShowsThatAValueOtherThanOneIsNotOne) {
  EXPECT_EQ(formatNear1(1.0), "1.000");
  EXPECT_EQ(formatNear1(659121.0 / 659120.0), "1.000002");
  EXPECT_EQ(formatNear1(0.9999), "0.9999");
  EXPECT_EQ(formatNear1(0.98765), "0.988");
  EXPECT_EQ(formatNear1(1.25), "1.250");
  EXPECT_EQ(formatNear1(2.0), "2.000");
}

}  // namespace
}  // namespace hb
