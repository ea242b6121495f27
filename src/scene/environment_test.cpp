// The environment's JSON form and the CPU lookup (scene/environment.h): the committed sky reads
// back as its generator wrote it, the lookup is exact at texel centres and wraps in azimuth, a
// rotation turns the sky, and every bad input is one line naming the key, the file and the fix
// (a glTF's extras.environment: gltf/gltf_extensions_test.cpp).
#include "scene/environment.h"

#include <cmath>
#include <fstream>
#include <iterator>

#include <unistd.h>

#include <gtest/gtest.h>

#include "base/errors.h"
#include "base/numbers.h"

#ifndef HYBRIDBENCH_SOURCE_DIR
#error "HYBRIDBENCH_SOURCE_DIR must name the source tree (for scenes/environments/)"
#endif

namespace hb {
namespace {

namespace fs = std::filesystem;
const fs::path kEnvironments = fs::path(HYBRIDBENCH_SOURCE_DIR) / "scenes/environments";

Environment read(const nlohmann::ordered_json& v, const fs::path& base = kEnvironments) {
  return readEnvironment(v, json_reader::Where{"cfg.json", "environment"}, base);
}

std::string errorOf(const nlohmann::ordered_json& v, const fs::path& base = kEnvironments) {
  try {
    read(v, base);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// The direction of texel (u, v)'s centre (scene.h Environment).
glm::dvec3 texelDirection(const Environment& e, uint32_t u, uint32_t v) {
  const double phi = 2.0 * kPi * (u + 0.5) / e.width - kPi, theta = kPi * (v + 0.5) / e.height;
  return {std::sin(phi) * std::sin(theta), std::cos(theta), -std::cos(phi) * std::sin(theta)};
}

// sky.mjs's ground colour below the horizon, [0.32, 0.27, 0.21], through RGBE: 8-bit mantissas
// under a shared exponent (0.32 < 2^-1: steps of 2^-9), so within 2^-9 below.
TEST(Environment, TheCommittedSkyReadsAsItsGeneratorWroteIt) {
  const Environment e = read({{"image", "sky.hdr"}});
  EXPECT_EQ(e.width, 128u);
  EXPECT_EQ(e.height, 64u);
  EXPECT_EQ(e.image, (kEnvironments / "sky.hdr").lexically_normal().string());
  const glm::vec3 ground = e.texels[size_t(e.height - 1) * e.width];
  const glm::vec3 written(0.32f, 0.27f, 0.21f);
  for (int c = 0; c < 3; ++c) {
    EXPECT_LE(ground[c], written[c]);
    EXPECT_GE(ground[c], written[c] - std::ldexp(1.0f, -9));
  }
  // The sun (sky.mjs: elevation 35°, azimuth 60° from -z towards +x) is the brightest direction.
  uint32_t best = 0;
  for (uint32_t i = 1; i < e.texels.size(); ++i)
    if (e.texels[i].r > e.texels[best].r) best = i;
  const glm::dvec3 d = texelDirection(e, best % e.width, best / e.width);
  EXPECT_NEAR(std::asin(d.y) * 180.0 / kPi, 35.0, 180.0 / 64.0);
  EXPECT_NEAR(std::atan2(d.x, -d.z) * 180.0 / kPi, 60.0, 360.0 / 128.0);
}

// At a texel's centre the bilinear weights are 0 and 1: the texel itself, times color·intensity
// (up to the direction's rounding, which moves it by ~1e-15 of a texel). Across the seam at
// azimuth ±180° the lookup wraps: the two edge columns' mean halfway between their centres.
TEST(Environment, TheLookupIsExactAtTexelCentresAndWrapsInAzimuth) {
  const Environment e = read({{"image", "sky.hdr"}, {"color", {0.5, 1.0, 2.0}}, {"intensity", 3.0}});
  for (uint32_t v : {0u, 17u, 40u, 63u})
    for (uint32_t u : {0u, 5u, 64u, 127u}) {
      const glm::dvec3 got = environmentRadiance(e, texelDirection(e, u, v));
      const glm::dvec3 want = glm::dvec3(e.texels[v * e.width + u]) * glm::dvec3(0.5, 1.0, 2.0) * 3.0;
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-9 * want[c] + 1e-12) << u << "," << v;
    }
  const uint32_t v = 20;
  const double theta = kPi * (v + 0.5) / e.height;
  const glm::dvec3 seam(0.0, std::cos(theta), std::sin(theta));  // φ = ±π: +z
  const glm::dvec3 got = environmentRadiance(e, seam);
  const glm::dvec3 want = 0.5 * (glm::dvec3(e.texels[v * e.width]) + glm::dvec3(e.texels[v * e.width + 127])) *
                          glm::dvec3(0.5, 1.0, 2.0) * 3.0;
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-9 * want[c]);
}

// "rotation": r turns the sky by r about +y: what was seen along d is then seen along R_y(r)·d.
TEST(Environment, ARotationTurnsTheSkyAboutTheVertical) {
  const Environment plain = read({{"image", "sky.hdr"}});
  const Environment turned = read({{"image", "sky.hdr"}, {"rotation", 90}});
  for (uint32_t v : {10u, 30u})
    for (uint32_t u : {3u, 70u}) {
      const glm::dvec3 d = texelDirection(plain, u, v);
      const glm::dvec3 r(d.z, d.y, -d.x);  // R_y(90°)·d, right-handed
      const glm::dvec3 a = environmentRadiance(plain, d), b = environmentRadiance(turned, r);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1e-9 * a[c]);
    }
}

TEST(Environment, AUniformColourNeedsNoImage) {
  const Environment e = read({{"color", {0.2, 0.4, 0.8}}, {"intensity", 2}});
  EXPECT_TRUE(e.image.empty());
  const glm::dvec3 l = environmentRadiance(e, {0.3, -0.9, 0.1});
  EXPECT_NEAR(l.b, 1.6, 1e-6);
  EXPECT_EQ(
      toJson(e),
      nlohmann::json::parse(
          R"({"color":[0.20000000298023224,0.4000000059604645,0.800000011920929],"intensity":2.0,"rotation":0.0})"));
}

// A fresh directory for one test, removed after it.
struct ScratchDir {
  fs::path path = fs::temp_directory_path() / ("hb_environment_" + std::to_string(::getpid()));
  ScratchDir() {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

TEST(Environment, BadInputIsOneLineNamingTheKeyAndTheFix) {
  ScratchDir dir;
  const fs::path png = dir.path / "x.png";
  std::ofstream(png) << "not an image";
  const fs::path bad = dir.path / "bad.hdr";
  std::ofstream(bad) << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 4\n";  // no pixels
  const fs::path cut = dir.path / "cut.hdr";  // the committed sky without its last 100 bytes
  {
    std::ifstream in(kEnvironments / "sky.hdr", std::ios::binary);
    std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(cut, std::ios::binary) << all.substr(0, all.size() - 100);
  }
  const struct {
    nlohmann::ordered_json value;
    std::vector<std::string> says;
  } cases[] = {
      {nlohmann::ordered_json::object(), {"cfg.json: environment", "neither \"image\" nor \"color\""}},
      {{{"image", "missing.hdr"}}, {"environment.image", "missing.hdr", "does not exist"}},
      {{{"image", png.string()}}, {"environment.image", "not a Radiance .hdr"}},
      {{{"image", bad.string()}}, {"environment.image", "truncated", "ends in scanline 0 of 4", "re-save"}},
      {{{"image", cut.string()}}, {"environment.image", "truncated", "re-save"}},
      {{{"color", {1, -1, 1}}}, {"environment.color", "negative"}},
      {{{"color", {1, 1, 1}}, {"intensity", -2}}, {"environment.intensity"}},
      {{{"color", {1, 1, 1}}, {"rotate", 3}}, {"environment", "rotate"}},
  };
  for (const auto& c : cases) {
    const std::string e = errorOf(c.value, dir.path);
    SCOPED_TRACE(c.value.dump());
    ASSERT_FALSE(e.empty());
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    for (const std::string& s : c.says) EXPECT_NE(e.find(s), std::string::npos) << e;
  }
}

}  // namespace
}  // namespace hb
