// Layered depth maps (Aalund et al. 2015, Sect. 3), built every frame so that scenes may move:
// per direction an orthographic map over the scene's bounding sphere (gpu_types.h LdmMap), every
// surface crossing of a pixel's line stored in a per-pixel list sorted by depth at construction.
// ldm_build=hardware: one instanced draw of the scene over the N maps, no attachments; each
// fragment inserts into its pixel's list (ldm_list=max64: 64-bit atomicMax, ldm_build.frag.glsl).
// ldm_build=3dr: the same lists from a compute rasterizer, one thread per (triangle, map) pair
// (ldm_build_3dr.comp.glsl: orthographic 3D edge functions), for GPUs with little raster hardware.
// The node pool is sized up front; fragments past it are counted (overflow), never silent.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>
#include "plan/ldm_settings.h"

#include "gpu/gpu_scene.h"
#include "gpu/gpu_timer.h"
#include "gpu/sync.h"
#include "gpu/vk_pipeline.h"
#include "gpu/vk_resources.h"
#include "shared/gpu_types.h"

namespace hb {

struct LdmCounters {
  uint64_t allocated = 0;      // nodes asked for (= fragments)
  uint64_t overflow = 0;       // fragments dropped because the pool was full
  uint64_t unfinished = 0;     // insertions cut at kLdmMaxInsertSteps
  uint64_t casRetries = 0;     // cas: compare-and-swaps another insertion won (then retried)
  uint64_t fp64Edges = 0;      // 3dr build: edge values within their rounding bound, decided in double
  uint64_t chunks = 0;         // 3dr build: 64-pixel chunks of the large pairs' boxes (insert or count phase)
  uint64_t chunkOverflow = 0;  // 3dr build: large pairs rasterized by their own thread (the chunk list was full)
};

// The 3dr build's balance (ldm_build_3dr.comp.glsl): a pair whose box holds more than smallBox pixel
// centres goes to the chunk list (~0u: never, 0: every pair), which holds chunkCapacity entries (0:
// 2·maps·R², what a build without a counting build gets, as tests make), each of chunkPixels
// pixels (a multiple of 64: a workgroup's threads take chunkPixels / 64 each).
struct LdmBuildTuning {
  uint32_t smallBox = gpu::kLdmSmallBox;
  uint32_t chunkCapacity = 0;
  uint32_t chunkPixels = gpu::kLdmChunk;
};

class LdmBuild {
 public:
  // maps: the N views (all of `resolution`²); nodeCapacity: the pool's nodes (>= 1). `scene` is
  // the one `gpuScene` holds (the compute build reads its world triangles). Throws InputError when
  // the device lacks what the method needs (64-bit buffer atomics; subgroup ballots in fragment
  // shaders for the hardware build).
  LdmBuild(const VulkanContext& ctx, const GpuScene& gpuScene, const Scene& scene, std::vector<gpu::LdmMap> maps,
           uint32_t resolution, uint32_t nodeCapacity, LdmBuildMethod method = LdmBuildMethod::Hardware,
           LdmList list = LdmList::Max64, LdmBuildTuning tuning = {});
  ~LdmBuild();

  // Clears the lists and draws them anew, declaring each step's accesses through `sync` (a frame's;
  // its readers declare theirs). With a timer, each step is a sub-pass of `pass` (subPasses).
  void record(VkCommandBuffer cmd, Sync& sync, GpuTimer* timer = nullptr, const std::string& pass = "") const;
  void record(VkCommandBuffer cmd) const;  // alone in its command buffer
  // The timer entries record() opens inside `pass`: "<pass>.insert" (max64, cas) or "<pass>.count",
  // ".scan", ".fill", ".sort" (sbuffer).
  std::vector<std::string> subPasses(const std::string& pass) const;
  uint32_t chunkCapacity() const { return chunkCapacity_; }
  uint32_t triangleCount() const { return triangleCount_; }

  uint32_t mapCount() const { return uint32_t(maps_.size()); }
  const std::vector<gpu::LdmMap>& maps() const { return maps_; }
  const Buffer& mapsBuffer() const { return mapsBuffer_; }
  uint32_t resolution() const { return resolution_; }
  uint32_t nodeCapacity() const { return nodeCapacity_; }
  const Buffer& links() const { return links_; }  // the list layout of gpu_types.h
  LdmList list() const { return list_; }
  // Bytes the fragments of a build need: the heads (sbuffer: offsets and cursors) and 8 bytes per
  // fragment (a 64-bit link; a 32-bit next or triangle id and a float depth).
  uint64_t exactBytes(uint64_t fragments) const;
  uint64_t memoryBytes() const { return links_.size() + mapsBuffer_.size() + counters_.size(); }

  // Readbacks. lists()[map·R² + pixel] is that pixel's depths, ascending, as stored (float).
  std::vector<std::vector<float>> readLists() const;
  // Each map pixel's list length (what the memory report needs, without the depths).
  std::vector<uint32_t> readListLengths() const;
  LdmCounters readCounters() const;

 private:
  const VulkanContext& ctx_;
  const GpuScene& scene_;
  std::vector<gpu::LdmMap> maps_;
  uint32_t resolution_, nodeCapacity_;
  LdmBuildMethod method_;
  LdmList list_;
  uint32_t triangleCount_ = 0;
  LdmBuildTuning tuning_;
  uint32_t chunkCapacity_ = 1;
  Buffer mapsBuffer_, links_, counters_, linksAddress_, triangles_, chunks_, blockSums_;
  Pipeline pipeline_;  // the build (sbuffer: its count pass)
  // sbuffer: the fill pass, and the scan's three stages and the sort (ldm_sbuffer.comp.glsl).
  std::unique_ptr<Pipeline> fill_, scan_[4];
  // 3dr: the listed chunks' pass after each pair pass (the insert or count phase, and the fill phase).
  std::unique_ptr<Pipeline> insertChunks_, fillChunks_;
  void recordGeometry(VkCommandBuffer cmd, Sync& sync, const Pipeline& p, const Pipeline* chunks) const;
  // The buffers the steps read and update, each as `a`.
  std::vector<Use> working(Access a) const;
};

// The N maps over the scene's bounding sphere: the AABB's centre and half its diagonal times
// (1 + 1e-6), as reference/ldm_ref.h ldmBoundingSphere, and ldmView's basis and pixel mapping.
std::vector<gpu::LdmMap> ldmMaps(const Scene& scene, const std::vector<glm::dvec3>& dirs, uint32_t resolution);

// The LDMs of an effect's settings (`effect` names it in errors): the pool is sized by a counting
// build (a pool of one node counts every fragment it drops), then allocated at the exact count
// plus 5 % for a scene that moves; overflow is counted. build: "hardware" | "3dr"; list: "max64" |
// "cas" | "sbuffer". Throws InputError when the fragments outgrow 32-bit node ids.
std::unique_ptr<LdmBuild> makeSizedLdmBuild(const VulkanContext& ctx, const GpuScene& gpuScene, const Scene& scene,
                                            const std::vector<glm::dvec3>& dirs, uint32_t resolution,
                                            LdmBuildMethod build, LdmList list, const char* effect);
// Where a pass that traces through LDMs gets them, given its directions: the frame's LDM set of
// its settings, built once per key and shared (frame_builder.h frameLdmSet).
using LdmSource = std::function<const LdmBuild&(const std::vector<glm::dvec3>& dirs)>;
// makeSizedLdmBuild's calls since the process started, for tests that count a frame's LDM sets.
uint64_t ldmSetBuildCount();

}  // namespace hb
