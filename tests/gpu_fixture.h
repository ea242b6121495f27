// Shared set-up for tests that run on the real Vulkan device present (lavapipe on CI): one
// context per test, and a check that the validation layers stayed silent.
#pragma once
#include <memory>

#include <gtest/gtest.h>

#include "gpu/vk_context.h"

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

}  // namespace hb::testing
