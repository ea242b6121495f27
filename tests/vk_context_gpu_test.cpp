// One process that opens and closes the device again and again: a test suite, or a tool that
// renders in several contexts, does. On the NVIDIA driver (580, an H200) a process could create no
// instance after about thirty had been created and destroyed: vkCreateInstance returned
// VK_ERROR_INCOMPATIBLE_DRIVER from then on, and every later GPU test of that process failed in its
// set-up (results/h200/gpu-tests-36). gpu/vk_context.cpp keeps the driver loaded.
#include <cstdio>
#include <memory>

#include <gtest/gtest.h>

#include "gpu/vk_context.h"

namespace hb {
namespace {

TEST(VulkanContextLifetime, OneProcessOpensAndClosesTheDeviceSixtyTimes) {
  // 60 contexts and 60 enumerations, 120 instances: about four times the ~30 that exhausted the
  // driver (there, without the fix, the sixteenth context failed).
  constexpr int kTimes = 60;
  int opened = 0;
  for (int i = 0; i < kTimes; ++i) {
    try {
      ASSERT_FALSE(enumerateDevices().empty());
      auto ctx = std::make_unique<VulkanContext>(0);
      ++opened;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "context " << i + 1 << " of " << kTimes << ": " << e.what();
      break;
    }
  }
  EXPECT_EQ(opened, kTimes);
  std::printf("[ context ] opened and closed the device %d times in one process\n", opened);
}

}  // namespace
}  // namespace hb
