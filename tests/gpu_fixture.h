// Shared set-up for tests that run on the real Vulkan device present (lavapipe on CI): one
// context per test, and a check that the validation layers stayed silent.
#pragma once
#include <memory>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

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
  std::unique_ptr<VulkanContext> ctx;
};

// A perspective camera at eye looking at target (y up), near 0.05 m, far 100 m: the GPU tests' scenes.
inline Camera lookFrom(glm::vec3 eye, glm::vec3 target) {
  Camera c;
  c.view = lookAt(eye, target, {0, 1, 0});
  c.znear = 0.05f;
  c.zfar = 100.0f;
  return c;
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
