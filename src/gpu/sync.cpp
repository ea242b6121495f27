#include "gpu/sync.h"

#include <algorithm>

#include "base/errors.h"
#include "gpu/vk_resources.h"

namespace hb {

namespace {

constexpr VkAccessFlags2 kWriteBits =
    VK_ACCESS_2_SHADER_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT |
    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_HOST_WRITE_BIT |
    VK_ACCESS_2_MEMORY_WRITE_BIT | VK_ACCESS_2_ACCELERATION_STRUCTURE_WRITE_BIT_KHR;

std::pair<uint64_t, uint32_t> keyOf(const SyncTarget& t) {
  if (t.img != VK_NULL_HANDLE) return {uint64_t(reinterpret_cast<uintptr_t>(t.img)), t.range.baseMipLevel};
  return {uint64_t(reinterpret_cast<uintptr_t>(t.buf)), 0};
}

}  // namespace

bool Access::writes() const { return (access & kWriteBits) != 0; }

SyncTarget::SyncTarget(const Buffer& b) : buf(b.handle()) {}

SyncTarget::SyncTarget(const Image& i)
    : img(i.handle()), range{i.aspect(), 0, i.mipLevels(), 0, 1}, layout(i.layoutRecord()) {}

SyncTarget SyncTarget::buffer(VkBuffer b) {
  SyncTarget t;
  t.buf = b;
  return t;
}

SyncTarget SyncTarget::image(VkImage i, VkImageSubresourceRange range, VkImageLayout* layout) {
  SyncTarget t;
  t.img = i;
  t.range = range;
  t.layout = layout;
  return t;
}

void Sync::assume(const SyncTarget& target, Access previous) {
  State& s = states_[keyOf(target)];
  s = State{};
  if (previous.writes()) {
    s.writeStages = previous.stages;
    s.writeAccess = previous.access & kWriteBits;
  } else {
    s.readStages = previous.stages;
  }
}

// One resource, one access: the barrier it needs after what the state says came before.
//  - a write, or a layout change (which writes the image), waits for the last write (its writes
//    made available) and for every read since it (an execution dependency: a read leaves nothing
//    to make available);
//  - a read waits for the last write unless that write has been made visible to its stages and
//    accesses already; a read after a read needs nothing.
void Sync::access(const SyncTarget& target, Access a, std::span<const Access> parts, Barriers& out) {
  HB_ASSERT(a.stages != VK_PIPELINE_STAGE_2_NONE);
  const bool image = target.img != VK_NULL_HANDLE;
  HB_ASSERT(!image || (target.layout && a.layout != VK_IMAGE_LAYOUT_UNDEFINED));  // an image access names its layout
  State& s = states_[keyOf(target)];
  const VkImageLayout from = image ? *target.layout : VK_IMAGE_LAYOUT_UNDEFINED;
  const bool transition = image && from != a.layout;
  VkPipelineStageFlags2 srcStages = VK_PIPELINE_STAGE_2_NONE;
  VkAccessFlags2 srcAccess = VK_ACCESS_2_NONE;
  bool barrier = false;
  if (a.writes() || transition) {
    srcStages = s.writeStages | s.readStages;
    srcAccess = s.writeAccess;
    barrier = transition || srcStages != VK_PIPELINE_STAGE_2_NONE;
    s.writeStages = a.stages;
    s.writeAccess = a.access & kWriteBits;
    s.readStages = a.writes() ? VK_PIPELINE_STAGE_2_NONE : a.stages;
    // Nothing has seen a new write yet; a layout change for reads is seen by the reads it was for.
    s.visible.clear();
    if (!a.writes()) s.visible.assign(parts.begin(), parts.end());
  } else {
    // Each declared read (of those merged into `a`) that the last write was not made visible to.
    Access unseen{};
    for (const Access& p : parts) {
      const bool seen = std::any_of(s.visible.begin(), s.visible.end(), [&](const Access& v) {
        return (p.stages & ~v.stages) == 0 && (p.access & ~v.access) == 0;
      });
      if (seen) continue;
      unseen.stages |= p.stages;
      unseen.access |= p.access;
      s.visible.push_back(p);
    }
    if (s.writeStages != VK_PIPELINE_STAGE_2_NONE && unseen.stages != VK_PIPELINE_STAGE_2_NONE) {
      srcStages = s.writeStages;
      srcAccess = s.writeAccess;
      barrier = true;
      a.stages = unseen.stages;  // the barrier's second scope: only what has not seen the write
      a.access = unseen.access;
    }
    s.readStages |= a.stages;
  }
  if (!barrier) return;
  if (image) {
    VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
    b.srcStageMask = srcStages;
    b.srcAccessMask = srcAccess;
    b.dstStageMask = a.stages;
    b.dstAccessMask = a.access;
    b.oldLayout = a.discards ? VK_IMAGE_LAYOUT_UNDEFINED : from;
    b.newLayout = a.layout;
    b.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = target.img;
    b.subresourceRange = target.range;
    out.images.push_back(b);
    *target.layout = a.layout;
  } else {
    VkBufferMemoryBarrier2 b{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER_2};
    b.srcStageMask = srcStages;
    b.srcAccessMask = srcAccess;
    b.dstStageMask = a.stages;
    b.dstAccessMask = a.access;
    b.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.buffer = target.buf;
    b.offset = 0;
    b.size = VK_WHOLE_SIZE;
    out.buffers.push_back(b);
  }
}

Barriers Sync::plan(std::span<const Use> uses) {
  // A resource named more than once is one access: the union of its stages and accesses (its
  // parts kept, to tell which of its reads have seen the last write).
  std::vector<Use> merged;
  std::vector<std::vector<Access>> parts;
  for (const Use& u : uses) {
    if (u.target.img == VK_NULL_HANDLE && u.target.buf == VK_NULL_HANDLE) continue;  // not made in this configuration
    auto same =
        std::find_if(merged.begin(), merged.end(), [&](const Use& m) { return keyOf(m.target) == keyOf(u.target); });
    if (same == merged.end()) {
      merged.push_back(u);
      parts.push_back({u.access});
      continue;
    }
    HB_ASSERT(same->target.img == VK_NULL_HANDLE || same->access.layout == u.access.layout);
    same->access.stages |= u.access.stages;
    same->access.access |= u.access.access;
    same->access.discards = same->access.discards && u.access.discards;
    parts[size_t(same - merged.begin())].push_back(u.access);
  }
  Barriers out;
  for (size_t i = 0; i < merged.size(); ++i) access(merged[i].target, merged[i].access, parts[i], out);
  return out;
}

void Sync::use(VkCommandBuffer cmd, std::span<const Use> uses) {
  const Barriers b = plan(uses);
  if (b.empty()) return;
  VkDependencyInfo di{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  di.bufferMemoryBarrierCount = uint32_t(b.buffers.size());
  di.pBufferMemoryBarriers = b.buffers.data();
  di.imageMemoryBarrierCount = uint32_t(b.images.size());
  di.pImageMemoryBarriers = b.images.data();
  vkCmdPipelineBarrier2(cmd, &di);
}

}  // namespace hb
