// Shared set-up for tests that run on the real Vulkan device present (lavapipe on CI): one
// context per test, and a check that the validation layers stayed silent.
#pragma once
#include <memory>
#include <string>
#include <string_view>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "config/config.h"
#include "frame/renderer.h"
#include "gpu/vk_context.h"
#include "scene/camera.h"
#include "scene/scene.h"

namespace hb::testing {

class GpuTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto devices = enumerateDevices();
    ASSERT_FALSE(devices.empty()) << "no Vulkan device: install mesa-vulkan-drivers (lavapipe)";
    ctx = std::make_unique<VulkanContext>(0);
  }
  void TearDown() override {
    if (ctx) {
      EXPECT_EQ(ctx->validationMessages(), 0u) << "validation layers reported messages (see stderr)";
    }
  }
  // The backend that traces a test's shadow rays where the tracer is not what the test checks (the
  // normals, the positions, what a hard case shadows): ray query where the device has it (lavapipe,
  // on which CI runs them), else the driver's ray-tracing pipeline (an NVIDIA H200 has no ray
  // query), else our own compute tracer. Each traces the same rays exactly as far as the tests ask.
  std::string exactBackend() const {
    if (ctx->info().rayQuery) return "rayquery";
    return ctx->info().rayTracingPipeline ? "pipeline" : "compute";
  }
  std::unique_ptr<VulkanContext> ctx;
};

// In a GpuTest's body: skips a test that compares ray query itself on a device without it, saying
// why (a test that only needs some exact tracer takes exactBackend() instead).
// (The empty branch first, as gtest's own macros do, so that an enclosing if's else stays its own.)
#define HB_SKIP_WITHOUT_RAY_QUERY()                    \
  if (ctx->info().rayQuery) {                          \
  } else                                               \
    GTEST_SKIP() << "the device (" << ctx->info().name \
                 << ") has no VK_KHR_ray_query, which this test compares with the other tracers"

// A perspective camera at eye looking at target (y up), near 0.05 m, far 100 m: the GPU tests' scenes.
inline Camera lookFrom(glm::vec3 eye, glm::vec3 target) {
  Camera c;
  c.view = lookAt(eye, target, {0, 1, 0});
  c.znear = 0.05f;
  c.zfar = 100.0f;
  return c;
}

// A setting by its config name ("3dr", "pipeline"), through the code's own names (toString):
// tests name settings as users write them. Fails the test on a name the code does not have.
template <typename Enum, size_t N>
Enum settingNamed(std::string_view name, const Enum (&values)[N]) {
  for (Enum v : values)
    if (name == toString(v)) return v;
  ADD_FAILURE() << "no setting named \"" << name << "\"";
  return values[0];
}
inline PrimaryMethod primaryNamed(std::string_view name) {
  static constexpr PrimaryMethod kAll[] = {PrimaryMethod::Hardware,
                                           PrimaryMethod::Raster3d,
                                           PrimaryMethod::Raster3dBinned,
                                           PrimaryMethod::Raster2d,
                                           PrimaryMethod::RayCast,
                                           PrimaryMethod::Raster2dBinned,
                                           PrimaryMethod::Raster3dFrustumCull,
                                           PrimaryMethod::Raster3dFrustumSplit,
                                           PrimaryMethod::Raster3dFull};
  return settingNamed(name, kAll);
}
inline RtBackend backendNamed(std::string_view name) {
  static constexpr RtBackend kAll[] = {RtBackend::Auto, RtBackend::RayQuery, RtBackend::Pipeline, RtBackend::Compute};
  return settingNamed(name, kAll);
}

// Settings of a width × height frame whose effects are `effects`, as a config's "effects" object
// names them ({"shadows": false, "indirect": {...}}); everything else at its default.
inline RenderSettings settingsWithEffects(uint32_t width, uint32_t height, const nlohmann::json& effects) {
  RenderSettings rs;
  rs.width = width;
  rs.height = height;
  rs.effects.add(EffectSource::Config, "test", effects);
  return rs;
}

}  // namespace hb::testing
