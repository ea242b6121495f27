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

// Only A-Z change: UTF-8 bytes (a scene file named "Ünïcode.GLB") pass through, so a multibyte
// name is never split or turned into other characters.
TEST(TextFormat, AsciiLowerChangesOnlyAsciiLetters) {
  EXPECT_EQ(asciiLower("Scene.GLTF"), "scene.gltf");
  EXPECT_EQ(asciiLower("GPU-5a1B2c3D"), "gpu-5a1b2c3d");
  EXPECT_EQ(asciiLower("\xC3\x9C"
                       "n\xC3\xAF"
                       "code.GLB"),
            "\xC3\x9C"
            "n\xC3\xAF"
            "code.glb");
  EXPECT_EQ(asciiLower("@[`{"), "@[`{");  // the bytes either side of A-Z and a-z
  EXPECT_EQ(asciiLower(""), "");
  EXPECT_EQ(asciiLower('Q'), 'q');
  EXPECT_EQ(asciiLower('['), '[');
}

}  // namespace
}  // namespace hb
