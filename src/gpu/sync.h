// Barriers from declared accesses. Before a command, its recorder declares what the command does to
// each buffer and image it touches (the pipeline stages, read or write, an image's layout); a Sync
// tracks every resource's last accesses over one command buffer and records exactly the barriers
// the new accesses need: read after write, write after read, write after write and a layout change
// each get one, a read after a read none, and the barriers of one declaration go out in one
// vkCmdPipelineBarrier2. This is the only place that records a barrier (docs/frame.md "Barriers").
//
// An Image carries the layout that the commands recorded so far leave it in (every command buffer
// here is submitted and waited for in the order it is recorded), so a Sync starts each image in the
// layout the last command buffer left it in. A resource's first access in a command buffer needs
// no barrier unless its layout changes or `assume` says what came before.
#pragma once
#include <cstdint>
#include <initializer_list>
#include <map>
#include <span>
#include <utility>
#include <vector>

#include <vulkan/vulkan.h>

namespace hb {

class Buffer;
class Image;

// What a command does to a resource: its stages, its accesses (reads and writes together) and, for
// an image, the layout it needs (buffers ignore it).
struct Access {
  VkPipelineStageFlags2 stages = VK_PIPELINE_STAGE_2_NONE;
  VkAccessFlags2 access = VK_ACCESS_2_NONE;
  VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
  // The command overwrites the whole image: a layout change may drop its contents (from UNDEFINED).
  bool discards = false;

  bool writes() const;
  // The same access to an image in another layout, or one that overwrites all of it.
  Access in(VkImageLayout l) const { return {stages, access, l, discards}; }
  Access discarding() const { return {stages, access, layout, true}; }
};

// The accesses the code makes. A "ray" stage is compute or ray tracing: a ray pass runs on either
// pipeline, chosen at run time.
namespace access {
constexpr VkPipelineStageFlags2 kRayStages =
    VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR;
constexpr VkAccessFlags2 kShaderReadWrite = VK_ACCESS_2_SHADER_READ_BIT | VK_ACCESS_2_SHADER_WRITE_BIT;
// Storage buffers and images read, or read and written, by a compute shader.
constexpr Access kComputeRead{VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_READ_BIT,
                              VK_IMAGE_LAYOUT_GENERAL};
constexpr Access kComputeWrite{VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, kShaderReadWrite, VK_IMAGE_LAYOUT_GENERAL};
// The same by a pass that traces with a compute or a ray-tracing pipeline.
constexpr Access kRayRead{kRayStages, VK_ACCESS_2_SHADER_READ_BIT, VK_IMAGE_LAYOUT_GENERAL};
constexpr Access kRayWrite{kRayStages, kShaderReadWrite, VK_IMAGE_LAYOUT_GENERAL};
// Read by a fragment shader.
constexpr Access kFragmentRead{VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_READ_BIT,
                               VK_IMAGE_LAYOUT_GENERAL};
// Read by a shader of any stage that a pass of the frame runs (shading is a draw or a dispatch).
constexpr Access kShaderRead{kRayStages | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_READ_BIT,
                             VK_IMAGE_LAYOUT_GENERAL};
// A depth image sampled by shaders, and tested without being written.
constexpr Access kDepthSampled{kRayStages | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                               VK_ACCESS_2_SHADER_SAMPLED_READ_BIT, VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL};
constexpr Access kDepthTest{VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                            VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT, VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL};
// Attachments of a draw.
constexpr Access kDepthAttachment{
    VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
    VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL};
constexpr Access kColorAttachment{VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                                  VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                                  VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
// A draw's vertices and indices.
constexpr Access kVertexInput{VK_PIPELINE_STAGE_2_VERTEX_INPUT_BIT,
                              VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT | VK_ACCESS_2_INDEX_READ_BIT};
// vkCmdFillBuffer and clears (all transfer stages: the spec counts a fill among the clears, the
// validation layer's synchronization checks (1.3.239) among the copies); copies from and into a
// resource.
constexpr Access kFill{VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                       VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL};
constexpr Access kCopyRead{VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT,
                           VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL};
constexpr Access kCopyWrite{VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                            VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL};
// Blits (a mip chain), and images sampled by any shader of the frame.
constexpr Access kBlitRead{VK_PIPELINE_STAGE_2_BLIT_BIT, VK_ACCESS_2_TRANSFER_READ_BIT,
                           VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL};
constexpr Access kBlitWrite{VK_PIPELINE_STAGE_2_BLIT_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                            VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL};
constexpr Access kSampled{kRayStages | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT,
                          VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
// Acceleration structure builds: the structures written, their inputs and scratch read.
constexpr Access kAccelBuildWrite{
    VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
    VK_ACCESS_2_ACCELERATION_STRUCTURE_READ_BIT_KHR | VK_ACCESS_2_ACCELERATION_STRUCTURE_WRITE_BIT_KHR};
constexpr Access kAccelBuildInput{VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                                  VK_ACCESS_2_SHADER_READ_BIT};
// Anything any command did or will do: what a resource's previous command buffer may have left
// (Sync::assume), or the access of a reader this code does not know.
constexpr Access kAnyWrite{VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT};
constexpr Access kAnyAccess{VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                            VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT};
}  // namespace access

// A buffer (whole) or an image (every mip) as a barrier names it.
struct SyncTarget {
  SyncTarget(const Buffer& b);
  SyncTarget(const Image& i);
  // Raw handles (tests without a device), or some mip levels of an image that go their own ways (a
  // mip chain's blits). `layout` is their current layout, updated as transitions are recorded.
  static SyncTarget buffer(VkBuffer b);
  static SyncTarget image(VkImage i, VkImageSubresourceRange range, VkImageLayout* layout);

  VkBuffer buf = VK_NULL_HANDLE;
  VkImage img = VK_NULL_HANDLE;
  VkImageSubresourceRange range{};
  VkImageLayout* layout = nullptr;  // images: the Image's own record of its layout

 private:
  SyncTarget() = default;
};

// One declared access: a command does `access` to `target`.
struct Use {
  SyncTarget target;
  Access access;
};

// The barriers a declaration needs, as one vkCmdPipelineBarrier2 records them.
struct Barriers {
  std::vector<VkBufferMemoryBarrier2> buffers;
  std::vector<VkImageMemoryBarrier2> images;
  bool empty() const { return buffers.empty() && images.empty(); }
};

class Sync {
 public:
  // Declares the accesses of the commands recorded next and records the barriers they need, all in
  // one call (none when none is needed). A resource named twice has the union of its accesses
  // (precondition for an image: one layout). A null one (not made in this configuration) is skipped.
  void use(VkCommandBuffer cmd, std::span<const Use> uses);
  void use(VkCommandBuffer cmd, std::initializer_list<Use> uses) { use(cmd, std::span(uses.begin(), uses.size())); }
  // The barriers of `use` without recording them; the state advances as if they were recorded.
  Barriers plan(std::span<const Use> uses);
  // `target`'s last access before this command buffer, when the commands before it are not
  // known to have finished (a readback after a frame: today every submit is waited for, and
  // `kAnyWrite` keeps the barrier such a readback has always had).
  void assume(const SyncTarget& target, Access previous);

 private:
  // A resource's accesses since its last write, over this command buffer.
  struct State {
    VkPipelineStageFlags2 writeStages = VK_PIPELINE_STAGE_2_NONE;  // the last write (or layout change)
    VkAccessFlags2 writeAccess = VK_ACCESS_2_NONE;                 // its writes, to make available
    VkPipelineStageFlags2 readStages = VK_PIPELINE_STAGE_2_NONE;   // reads since, to wait for before a write
    std::vector<Access> visible;  // (stages, accesses) the last write has been made visible to
  };
  // `a` is the union of `parts`, the accesses declared for the resource in one `use`.
  void access(const SyncTarget& target, Access a, std::span<const Access> parts, Barriers& out);
  std::map<std::pair<uint64_t, uint32_t>, State> states_;  // by handle and first mip level
};

}  // namespace hb
