// The environment light on the real device (effects/environment_light/env_effect.h): the GPU's
// lookup of the environment against the CPU's, a uniform environment equal to its colour times the
// ambient occlusion of the same directions (ldm, raytraced, reference), an open plane equal to the
// CPU's quadrature of the committed sky, the shading adding albedo·E, and nothing built when the
// scene has no environment.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "effects/ambient_occlusion/ao_part.h"
#include "effects/environment_light/env_part.h"
#include "environment_lookup_comp.h"  // generated from tests/shaders/environment_lookup.comp.glsl
#include "frame/renderer.h"
#include "gpu/descriptor_binder.h"
#include "gpu/vk_pipeline.h"
#include "gpu/vk_resources.h"
#include "gpu_fixture.h"
#include "reference/eq_partition.h"
#include "scene/atrium.h"
#include "scene/environment.h"
#include "scene/mesh_builder.h"
#include "shared/gpu_types.h"

namespace hb {
namespace {

namespace fs = std::filesystem;
constexpr double kU = 1.0 / 16777216.0;  // float's unit roundoff, 2^-24

// The committed sky (scenes/environments/sky.mjs), turned and tinted so that every part of the
// mapping is used.
Environment committedSky(float rotation = 40.0f) {
  nlohmann::ordered_json v = {
      {"image", "sky.hdr"}, {"color", {0.9, 1.0, 1.1}}, {"intensity", 1.3}, {"rotation", rotation}};
  return readEnvironment(v, json_reader::Where{"test", "environment"},
                         fs::path(HYBRIDBENCH_SOURCE_DIR) / "scenes/environments");
}

std::vector<float> floatsOf(const std::vector<uint8_t>& bytes) {
  std::vector<float> out(bytes.size() / sizeof(float));
  std::memcpy(out.data(), bytes.data(), out.size() * sizeof(float));
  return out;
}

// A ground quad of side 40 m at y = 0 with a matte white material, seen from 3 m above.
Scene openPlane() {
  Scene s;
  s.name = "open-plane";
  Material m;
  m.metallicFactor = 0.0f;
  s.materials.push_back(m);
  MeshBuilder mb("ground");
  addQuad(mb, 0, {-20, 0, -20}, {20, 0, -20}, {20, 0, 20}, {-20, 0, 20}, {0, 1, 0});
  mb.appendTo(s);
  Light l;
  l.position = {0, 5, 0};
  l.intensity = 20.0f;
  l.range = 30.0f;
  s.lights.push_back(l);
  s.cameras.push_back(testing::lookFrom({0, 3, 4}, {0, 0, -2}));
  return s;
}

RenderSettings envSettings(uint32_t w, uint32_t h, const nlohmann::json& effects) {
  return testing::settingsWithEffects(w, h, effects);
}

class EnvironmentGpuTest : public testing::GpuTest {
 protected:
  void SetUp() override {
    testing::GpuTest::SetUp();
    static const bool spirv = (registerSpirv("environment_lookup.comp", kSpirv_environment_lookup_comp,
                                             sizeof kSpirv_environment_lookup_comp),
                               true);
    (void)spirv;
  }
};

// The shader's lookup against the CPU's in double, along 4096 random directions (|y| <= 0.99: at
// the poles the azimuth is ill-conditioned in both). Bound per channel, derived from Vulkan's
// precision of the shader's operations: atan and acos carry up to 4096 ULP of an angle below π
// (2^-22 each: 1e-3 rad); the rotation's float products move the direction by ~3u, which acos
// turns into at most 3u/sqrt(1 - 0.99²) = 21u rad. An angle error δ moves the texel coordinate by
// δ·size/(2π) (u) or δ·size/π (v), and the bilinear value by at most that times the largest step
// between neighbouring texels; the three mixes and the scale add 8u of the value.
TEST_F(EnvironmentGpuTest, TheShadersLookupIsTheCpusWithinFloatPrecision) {
  const Environment env = committedSky();
  ASSERT_EQ(env.width, 128u);
  ASSERT_EQ(env.height, 64u);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  std::vector<glm::vec4> dirs;
  while (dirs.size() < 4096) {
    const glm::dvec3 d(uni(rng), uni(rng), uni(rng));
    const double len = glm::length(d);
    if (len > 1.0 || len < 0.1 || std::abs(d.y / len) > 0.99) continue;
    dirs.emplace_back(glm::vec3(d / len), 0.0f);
  }
  gpu::AoConstants c{};
  c.envWidth = env.width;
  c.envHeight = env.height;
  c.envScale = glm::vec4(env.color * env.intensity, 0.0f);
  const double a = double(env.rotationDegrees) * 3.14159265358979323846 / 180.0;
  c.envRotation = glm::vec4(float(std::cos(a)), float(std::sin(a)), 0.0f, 0.0f);
  std::vector<glm::vec4> texels;
  for (const glm::vec3& t : env.texels) texels.emplace_back(t, 0.0f);
  Buffer params = uploadBuffer(*ctx, &c, sizeof c, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, MemClass::Other);
  Buffer in = uploadBuffer(*ctx, dirs.data(), dirs.size() * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                           MemClass::Other);
  Buffer map = uploadBuffer(*ctx, texels.data(), texels.size() * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                            MemClass::Other);
  Buffer out(*ctx, dirs.size() * sizeof(glm::vec4),
             VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT, false, MemClass::Other);
  DescriptorBinder binder("environment_lookup");
  binder.provide("Params", params);
  binder.provide("Directions", in);
  binder.provide("Out", out);
  binder.provide("EnvironmentMap", map);  // environment.glsl.inc's, as ambient occlusion binds it
  Pipeline pipeline(*ctx);
  pipeline.createCompute(binder, "environment_lookup.comp", sizeof(uint32_t));
  binder.checkEveryNameRead();
  const uint32_t count = uint32_t(dirs.size());
  ctx->submitAndWait([&](VkCommandBuffer cmd) {
    VkDescriptorSet set = pipeline.set();
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.handle());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.layout(), 0, 1, &set, 0, nullptr);
    vkCmdPushConstants(cmd, pipeline.layout(), VK_SHADER_STAGE_ALL, 0, sizeof count, &count);
    vkCmdDispatch(cmd, (count + 63) / 64, 1, 1);
  });
  const std::vector<float> got = floatsOf(readbackBuffer(*ctx, out));

  // The largest step between neighbouring texels (wrapping in u), per channel, and the largest value.
  glm::dvec3 stepU(0.0), stepV(0.0), top(0.0);
  for (uint32_t y = 0; y < env.height; ++y)
    for (uint32_t x = 0; x < env.width; ++x) {
      const glm::dvec3 t(env.texels[y * env.width + x]);
      top = glm::max(top, t);
      stepU = glm::max(stepU, glm::abs(t - glm::dvec3(env.texels[y * env.width + (x + 1) % env.width])));
      if (y + 1 < env.height) stepV = glm::max(stepV, glm::abs(t - glm::dvec3(env.texels[(y + 1) * env.width + x])));
    }
  const double angle = 4096.0 * std::ldexp(1.0, -22) + 21.0 * kU;
  const glm::dvec3 scale = glm::dvec3(env.color) * double(env.intensity);
  const glm::dvec3 bound = (angle * env.width / (2.0 * 3.14159265358979323846) * stepU +
                            angle * env.height / 3.14159265358979323846 * stepV + 8.0 * kU * top) *
                           scale;
  double worst = 0.0;
  for (size_t i = 0; i < dirs.size(); ++i) {
    const glm::dvec3 want = environmentRadiance(env, glm::dvec3(dirs[i]));
    for (int ch = 0; ch < 3; ++ch) {
      const double d = std::abs(double(got[4 * i + ch]) - want[ch]);
      worst = std::max(worst, d / bound[ch]);
      ASSERT_LE(d, bound[ch]) << "direction " << i << " channel " << ch << ": GPU " << got[4 * i + ch] << ", CPU "
                              << want[ch];
    }
  }
  std::printf("environment lookup: 4096 directions, largest difference %.3g of the derived bound\n", worst);
}

// A uniform environment c: the light is c·AO by definition, and the pass computes it with the same
// visibility as ambient occlusion of the same settings (the same directions, maps and rays). The
// sums differ only in rounding: ldm and raytraced add N products |n·v|·c against c times the sum
// of N terms |n·v| (all positive): within (2N + 4)u of c·AO relatively; reference adds S radiances
// from three bilinear mixes of equal texels (each within 2u of the texel) and the scale against
// S ones: within (S + 8)u.
TEST_F(EnvironmentGpuTest, AUniformEnvironmentIsItsColourTimesTheAmbientOcclusion) {
  Scene scene = makeAtrium(AtriumParams{});
  scene.ambient = Ambient{{1, 1, 1}, 1.0f};
  nlohmann::ordered_json uniform = {{"color", {0.5, 1.0, 2.0}}, {"intensity", 0.7}};
  scene.environment = readEnvironment(uniform, json_reader::Where{"test", "environment"}, {});
  const glm::dvec3 c = glm::dvec3(0.5, 1.0, 2.0) * double(0.7f);
  for (const char* method : {"ldm", "raytraced", "reference"}) {
    SCOPED_TRACE(method);
    const nlohmann::json settings = {{"method", method}, {"directions", 16}, {"ldm_resolution", 64}, {"samples", 64}};
    Renderer r(
        *ctx, scene,
        envSettings(96, 54, {{"shadows", true}, {"ambient_occlusion", settings}, {"environment_light", settings}}));
    r.renderFrame(true);
    const std::vector<float> ao = aoPassOf(r)->readAo();
    const std::vector<float> env = environmentPassOf(r)->readAo();
    ASSERT_EQ(env.size(), 4 * ao.size());
    const double terms = std::string(method) == "reference" ? 64.0 + 8.0 : 2.0 * 16.0 + 4.0;
    size_t valued = 0;
    for (size_t i = 0; i < ao.size(); ++i) {
      if (ao[i] < 0.0f) {
        ASSERT_EQ(env[4 * i + 3], ao[i]) << "pixel " << i << ": the status (sky, no normal) is AO's";
        continue;
      }
      ++valued;
      ASSERT_EQ(env[4 * i + 3], 1.0f) << "pixel " << i;
      for (int ch = 0; ch < 3; ++ch) {
        const double want = c[ch] * double(ao[i]);
        ASSERT_NEAR(double(env[4 * i + ch]), want, terms * kU * c[ch] * std::max(double(ao[i]), 1e-30) + 1e-30)
            << "pixel " << i << " channel " << ch;
      }
    }
    EXPECT_GT(valued, ao.size() / 2);
  }
}

// An open plane under the committed sky: every direction of the upper hemisphere is free, so each
// pixel's raytraced value is the quadrature (2/N)·Σ_i |v_i·y|·L(s_i·v_i) with the CPU's radiances
// along the directions (the true face normal y through 3D rasterization's geometric normals: the
// plane's vertices lie in y = 0, so its normal is y to within inversesqrt's 2 ULP). The GPU adds
// the same N positive terms in float: within (N + 6)u of the sum per channel.
TEST_F(EnvironmentGpuTest, AnOpenPlaneSeesTheQuadratureOfTheSkyAlongItsDirections) {
  Scene scene = openPlane();
  scene.environment = committedSky();
  constexpr uint32_t kN = 64;
  RenderSettings rs =
      envSettings(64, 36, {{"shadows", true}, {"environment_light", {{"method", "raytraced"}, {"directions", kN}}}});
  rs.primary = testing::primaryNamed("3dr");
  rs.worldPos = WorldPosMethod::Hit;
  rs.normals = NormalCulling::Geometric;
  Renderer r(*ctx, scene, rs);
  r.renderFrame(true);
  const std::vector<float> got = environmentPassOf(r)->readAo();
  glm::dvec3 want(0.0);
  for (const glm::dvec3& v : ldmDirections(kN)) {
    if (v.y == 0.0) continue;
    const double s = v.y > 0.0 ? 1.0 : -1.0;
    want += std::abs(v.y) * environmentRadiance(*scene.environment, s * v);
  }
  want *= 2.0 / double(kN);
  size_t valued = 0;
  for (size_t i = 0; i < got.size() / 4; ++i) {
    if (got[4 * i + 3] != 1.0f) continue;
    ++valued;
    for (int ch = 0; ch < 3; ++ch)
      ASSERT_NEAR(double(got[4 * i + ch]), want[ch], (kN + 6) * kU * want[ch]) << "pixel " << i << " channel " << ch;
  }
  EXPECT_GT(valued, got.size() / 4 / 2);
}

// Shading adds albedo·(1 − metallic)·E where the effect runs: the frame with it minus the frame
// without it is the white plane's E, to the RGBA16F colour's rounding of both: Vulkan lets the
// conversion to a 16-bit float round to nearest or towards zero, so within one ULP, 2^-10 of each
// value relatively.
TEST_F(EnvironmentGpuTest, ShadingAddsTheLightTimesTheAlbedo) {
  Scene scene = openPlane();
  scene.environment = committedSky();
  const nlohmann::json on = {{"shadows", true}, {"environment_light", {{"method", "raytraced"}, {"directions", 16}}}};
  Renderer with(*ctx, scene, envSettings(48, 27, on));
  with.renderFrame(true);
  Renderer without(*ctx, scene, envSettings(48, 27, {{"shadows", true}, {"environment_light", false}}));
  without.renderFrame(true);
  const std::vector<float> a = with.readColor(), b = without.readColor();
  const std::vector<float> e = environmentPassOf(with)->readAo();
  EXPECT_EQ(environmentPassOf(without), nullptr);
  size_t compared = 0;
  for (size_t i = 0; i < e.size() / 4; ++i) {
    if (e[4 * i + 3] != 1.0f) continue;
    ++compared;
    for (int ch = 0; ch < 3; ++ch)
      ASSERT_NEAR(a[4 * i + ch] - b[4 * i + ch], e[4 * i + ch],
                  std::ldexp(1.0, -10) * (std::abs(a[4 * i + ch]) + std::abs(b[4 * i + ch])) + 1e-6)
          << "pixel " << i << " channel " << ch;
  }
  EXPECT_GT(compared, e.size() / 4 / 2);
}

// Without an environment the effect cannot act: no pass, no buffer, and the reason recorded.
TEST_F(EnvironmentGpuTest, ASceneWithoutAnEnvironmentBuildsNothingForIt) {
  const Scene scene = openPlane();
  Renderer r(*ctx, scene, envSettings(32, 18, {{"shadows", true}, {"environment_light", true}}));
  r.renderFrame(true);
  EXPECT_EQ(environmentPassOf(r), nullptr);
  bool skipped = false;
  for (const auto& [pass, reason] : r.plan().skipped)
    skipped = skipped || (pass == kEnvironmentLightPass && reason.find("no environment") != std::string::npos);
  EXPECT_TRUE(skipped);
}

}  // namespace
}  // namespace hb
