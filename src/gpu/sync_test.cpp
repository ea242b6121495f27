// Which barrier a Sync records for which pair of accesses; no device: the handles are stand-ins.
#include "gpu/sync.h"

#include <gtest/gtest.h>

namespace hb {
namespace {

VkBuffer fakeBuffer(uintptr_t n) { return reinterpret_cast<VkBuffer>(n); }
VkImage fakeImage(uintptr_t n) { return reinterpret_cast<VkImage>(n); }

Barriers plan(Sync& sync, std::initializer_list<Use> uses) { return sync.plan(std::span(uses.begin(), uses.size())); }

TEST(Sync, AFirstAccessInTheCommandBufferNeedsNoBarrier) {
  Sync sync;
  const SyncTarget a = SyncTarget::buffer(fakeBuffer(1)), b = SyncTarget::buffer(fakeBuffer(2));
  EXPECT_TRUE(plan(sync, {{a, access::kComputeWrite}, {b, access::kComputeRead}}).empty());
}

TEST(Sync, ReadAfterWriteWaitsForTheWriteAndMakesItVisible) {
  Sync sync;
  const SyncTarget a = SyncTarget::buffer(fakeBuffer(1));
  plan(sync, {{a, access::kComputeWrite}});
  const Barriers b = plan(sync, {{a, access::kFragmentRead}});
  ASSERT_EQ(b.buffers.size(), 1u);
  EXPECT_TRUE(b.images.empty());
  EXPECT_EQ(b.buffers[0].buffer, fakeBuffer(1));
  EXPECT_EQ(b.buffers[0].srcStageMask, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
  EXPECT_EQ(b.buffers[0].srcAccessMask, VK_ACCESS_2_SHADER_WRITE_BIT);  // the write's bits, not its reads
  EXPECT_EQ(b.buffers[0].dstStageMask, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT);
  EXPECT_EQ(b.buffers[0].dstAccessMask, VK_ACCESS_2_SHADER_READ_BIT);
}

TEST(Sync, ReadAfterReadNeedsNoBarrier) {
  Sync sync;
  const SyncTarget a = SyncTarget::buffer(fakeBuffer(1));
  plan(sync, {{a, access::kComputeWrite}});
  EXPECT_FALSE(plan(sync, {{a, access::kComputeRead}}).empty());
  EXPECT_TRUE(plan(sync, {{a, access::kComputeRead}}).empty());
  // A reader in a stage the write was not yet made visible to needs its own barrier, from the write.
  const Barriers copy = plan(sync, {{a, access::kCopyRead}});
  ASSERT_EQ(copy.buffers.size(), 1u);
  EXPECT_EQ(copy.buffers[0].srcStageMask, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT);
  EXPECT_EQ(copy.buffers[0].dstStageMask, VK_PIPELINE_STAGE_2_COPY_BIT);
  EXPECT_TRUE(plan(sync, {{a, access::kCopyRead}, {a, access::kComputeRead}}).empty());
}

TEST(Sync, WriteAfterReadWaitsForEveryReadWithNothingToMakeAvailable) {
  Sync sync;
  const SyncTarget a = SyncTarget::buffer(fakeBuffer(1));
  plan(sync, {{a, access::kFragmentRead}});
  plan(sync, {{a, access::kCopyRead}});
  const Barriers b = plan(sync, {{a, access::kFill}});
  ASSERT_EQ(b.buffers.size(), 1u);
  EXPECT_EQ(b.buffers[0].srcStageMask, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COPY_BIT);
  EXPECT_EQ(b.buffers[0].srcAccessMask, VK_ACCESS_2_NONE);
  EXPECT_EQ(b.buffers[0].dstStageMask, access::kFill.stages);
  EXPECT_EQ(b.buffers[0].dstAccessMask, VK_ACCESS_2_TRANSFER_WRITE_BIT);
}

TEST(Sync, WriteAfterWriteWaitsForTheWrite) {
  Sync sync;
  const SyncTarget a = SyncTarget::buffer(fakeBuffer(1));
  plan(sync, {{a, access::kFill}});
  const Barriers b = plan(sync, {{a, access::kComputeWrite}});
  ASSERT_EQ(b.buffers.size(), 1u);
  EXPECT_EQ(b.buffers[0].srcStageMask, access::kFill.stages);
  EXPECT_EQ(b.buffers[0].srcAccessMask, VK_ACCESS_2_TRANSFER_WRITE_BIT);
  EXPECT_EQ(b.buffers[0].dstAccessMask, VK_ACCESS_2_SHADER_READ_BIT | VK_ACCESS_2_SHADER_WRITE_BIT);
  // Dispatch after dispatch on one buffer: each waits for the one before.
  EXPECT_EQ(plan(sync, {{a, access::kComputeWrite}}).buffers.size(), 1u);
  EXPECT_EQ(plan(sync, {{a, access::kComputeWrite}}).buffers.size(), 1u);
}

TEST(Sync, ALayoutChangeIsABarrierEvenOnAFirstAccessAndMovesTheImagesLayout) {
  Sync sync;
  VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
  const SyncTarget depth = SyncTarget::image(fakeImage(7), {VK_IMAGE_ASPECT_DEPTH_BIT, 0, 1, 0, 1}, &layout);
  Barriers b = plan(sync, {{depth, access::kCopyWrite}});
  ASSERT_EQ(b.images.size(), 1u);
  EXPECT_EQ(b.images[0].oldLayout, VK_IMAGE_LAYOUT_UNDEFINED);
  EXPECT_EQ(b.images[0].newLayout, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
  EXPECT_EQ(b.images[0].srcStageMask, VK_PIPELINE_STAGE_2_NONE);
  EXPECT_EQ(b.images[0].subresourceRange.aspectMask, VkImageAspectFlags(VK_IMAGE_ASPECT_DEPTH_BIT));
  EXPECT_EQ(layout, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
  // Read in another layout: the transition waits for the copy and makes its write visible.
  b = plan(sync, {{depth, access::kDepthSampled}});
  ASSERT_EQ(b.images.size(), 1u);
  EXPECT_EQ(b.images[0].oldLayout, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
  EXPECT_EQ(b.images[0].newLayout, VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL);
  EXPECT_EQ(b.images[0].srcStageMask, VK_PIPELINE_STAGE_2_COPY_BIT);
  EXPECT_EQ(b.images[0].srcAccessMask, VK_ACCESS_2_TRANSFER_WRITE_BIT);
  EXPECT_EQ(layout, VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL);
  EXPECT_TRUE(plan(sync, {{depth, access::kDepthSampled}}).empty());
  // The depth test reads it in the same layout, in stages the transition has not reached yet.
  b = plan(sync, {{depth, access::kDepthTest}});
  ASSERT_EQ(b.images.size(), 1u);
  EXPECT_EQ(b.images[0].oldLayout, b.images[0].newLayout);
  EXPECT_EQ(b.images[0].srcStageMask, access::kDepthSampled.stages);
}

TEST(Sync, AnAccessThatOverwritesTheImageDropsItsContentsInTheTransition) {
  Sync sync;
  VkImageLayout layout = VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL;
  const SyncTarget depth = SyncTarget::image(fakeImage(7), {VK_IMAGE_ASPECT_DEPTH_BIT, 0, 1, 0, 1}, &layout);
  plan(sync, {{depth, access::kDepthSampled}});
  const Barriers b = plan(sync, {{depth, access::kCopyWrite.discarding()}});
  ASSERT_EQ(b.images.size(), 1u);
  EXPECT_EQ(b.images[0].oldLayout, VK_IMAGE_LAYOUT_UNDEFINED);
  EXPECT_EQ(b.images[0].srcStageMask, access::kDepthSampled.stages);  // after its readers all the same
  EXPECT_EQ(layout, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
}

TEST(Sync, MipLevelsDeclaredApartAreTrackedApart) {
  Sync sync;
  VkImageLayout layouts[2] = {VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_UNDEFINED};
  const SyncTarget mip0 = SyncTarget::image(fakeImage(9), {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1}, &layouts[0]);
  const SyncTarget mip1 = SyncTarget::image(fakeImage(9), {VK_IMAGE_ASPECT_COLOR_BIT, 1, 1, 0, 1}, &layouts[1]);
  plan(sync, {{mip0, access::kCopyWrite.discarding()}});
  const Barriers b = plan(sync, {{mip0, access::kBlitRead}, {mip1, access::kBlitWrite.discarding()}});
  ASSERT_EQ(b.images.size(), 2u);
  EXPECT_EQ(b.images[0].subresourceRange.baseMipLevel, 0u);
  EXPECT_EQ(b.images[0].srcAccessMask, VK_ACCESS_2_TRANSFER_WRITE_BIT);  // the copy into level 0
  EXPECT_EQ(b.images[1].subresourceRange.baseMipLevel, 1u);
  EXPECT_EQ(b.images[1].srcStageMask, VK_PIPELINE_STAGE_2_NONE);  // level 1: nothing before it
  EXPECT_EQ(layouts[0], VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
  EXPECT_EQ(layouts[1], VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
}

TEST(Sync, ANullResourceIsSkipped) {
  Sync sync;
  EXPECT_TRUE(plan(sync, {{SyncTarget::buffer(VK_NULL_HANDLE), access::kComputeWrite}}).empty());
}

TEST(Sync, OneDeclarationIsOneBarrierCallAndARepeatedResourceIsOneAccess) {
  Sync sync;
  VkImageLayout layout = VK_IMAGE_LAYOUT_GENERAL;
  const SyncTarget a = SyncTarget::buffer(fakeBuffer(1)), b = SyncTarget::buffer(fakeBuffer(2));
  const SyncTarget img = SyncTarget::image(fakeImage(3), {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1}, &layout);
  plan(sync, {{a, access::kComputeWrite}, {b, access::kComputeWrite}, {img, access::kComputeWrite}});
  const Barriers all = plan(
      sync,
      {{a, access::kFragmentRead}, {b, access::kComputeRead}, {b, access::kFragmentRead}, {img, access::kComputeRead}});
  ASSERT_EQ(all.buffers.size(), 2u);
  ASSERT_EQ(all.images.size(), 1u);
  EXPECT_EQ(all.buffers[1].buffer, fakeBuffer(2));
  EXPECT_EQ(all.buffers[1].dstStageMask,
            VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT);
  EXPECT_EQ(all.images[0].oldLayout, VK_IMAGE_LAYOUT_GENERAL);
  EXPECT_EQ(all.images[0].newLayout, VK_IMAGE_LAYOUT_GENERAL);
}

TEST(Sync, AnAssumedEarlierWriteIsWaitedFor) {
  Sync sync;
  const SyncTarget a = SyncTarget::buffer(fakeBuffer(1));
  sync.assume(a, access::kAnyWrite);
  const Barriers b = plan(sync, {{a, access::kCopyRead}});
  ASSERT_EQ(b.buffers.size(), 1u);
  EXPECT_EQ(b.buffers[0].srcStageMask, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT);
  EXPECT_EQ(b.buffers[0].srcAccessMask, VK_ACCESS_2_MEMORY_WRITE_BIT);
}

}  // namespace
}  // namespace hb
