#include "frame/passes/light_culling.h"

#include <algorithm>
#include <cmath>

#include "base/errors.h"
#include "frame/passes/depth_prepass.h"
#include "gpu/descriptor_binder.h"
#include "shared/gpu_types.h"

namespace hb {

namespace {
uint32_t listModeOf(LightLists l) { return uint32_t(l); }  // the enum's values are the shaders' kList*

VkDeviceSize listWords(const CullingSettings& s, uint32_t tiles, uint32_t maskWords) {
  if (s.lists == LightLists::Tile) return VkDeviceSize(tiles) * s.capacity;
  return VkDeviceSize(tiles) * maskWords + (s.lists == LightLists::Zbin ? gpu::kZBins : 0);
}

}  // namespace

LightCulling::LightCulling(const VulkanContext& ctx, const CullingSettings& settings, uint32_t width, uint32_t height,
                           const Buffer& frameConstants, const Buffer& lights, const Image& depth, VkSampler sampler)
    : ctx_(ctx),
      settings_(settings),
      tilesX_((width + settings.tileSize - 1) / settings.tileSize),
      tilesY_((height + settings.tileSize - 1) / settings.tileSize),
      maskWords_(std::max<uint32_t>(1, (settings.lightCount + 31) / 32)),
      pixels_(double(width) * height),
      lights_(lights),
      frustums_(ctx, VkDeviceSize(tilesX_) * tilesY_ * sizeof(gpu::TileFrustum), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                false, MemClass::Culling),
      grid_(ctx, VkDeviceSize(tilesX_) * tilesY_ * sizeof(gpu::LightGridEntry),
            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT, false, MemClass::Culling),
      indices_(ctx, listWords(settings, tilesX_ * tilesY_, maskWords_) * sizeof(uint32_t),
               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT, false, MemClass::Culling),
      // zbin only; one element otherwise (never read).
      sortedLights_(
          ctx,
          (settings.lists == LightLists::Zbin ? std::max<uint32_t>(1, settings.lightCount) : 1) * sizeof(gpu::GpuLight),
          VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT, false, MemClass::Culling),
      order_(ctx,
             (settings.lists == LightLists::Zbin ? std::max<uint32_t>(1, settings.lightCount) : 1) * sizeof(uint32_t),
             VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT, false, MemClass::Culling),
      extents_(ctx, (settings.lists == LightLists::Zbin ? std::max<uint32_t>(1, settings.lightCount) : 1) * 8,
               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, MemClass::Culling),
      viewLights_(ctx, std::max<uint32_t>(1, settings.lightCount) * sizeof(gpu::GpuViewLight),
                  VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, MemClass::Culling),
      viewSpheres_(ctx, std::max<uint32_t>(1, settings.lightCount) * sizeof(glm::vec4),
                   VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, MemClass::Culling),
      frustumPipeline_(ctx),
      cullPipeline_(ctx),
      viewPipeline_(ctx),
      sortPipeline_(ctx),
      binPipeline_(ctx) {
  checkParam("tile_size", settings.tileSize);  // the config's own check (settings built without one)
  HB_ASSERT(settings.capacity == gpu::kMaxLightsPerTile);
  if (settings.lightCount > gpu::kMaxLights)
    throw InputError(std::to_string(settings.lightCount) + " lights: light culling handles at most " +
                     std::to_string(gpu::kMaxLights) + "; lower light_count");
  if (settings.lists == LightLists::Zbin && !(settings.zbinNear > 0.0f && settings.zbinFar > settings.zbinNear))
    throw InputError("light_lists=zbin: the bins need 0 < near < far (got " + std::to_string(settings.zbinNear) + ", " +
                     std::to_string(settings.zbinFar) + ")");
  if (settings.depthSlices == 1 || settings.depthSlices > 32)
    throw InputError("depth_slices " + std::to_string(settings.depthSlices) + " is not 0 (off) or 2..32");
  // Each of the five shaders gets its own set, from its reflection, written from one name table.
  DescriptorBinder binder("light_culling");
  binder.provide("Frame", frameConstants);
  binder.provide("Lights", lights);
  binder.provide("Frustums", frustums_);
  binder.provide("Grid", grid_);
  binder.provide("Indices", indices_);
  binder.provide("depthTex", depth, depthReadLayout(depth), sampler);
  binder.provide("SortedLights", sortedLights_);
  binder.provide("ViewLights", viewLights_);
  binder.provide("ViewSpheres", viewSpheres_);
  if (settings.lists == LightLists::Zbin) {  // what only the sort and the bins read
    binder.provide("Order", order_);
    binder.provide("Extents", extents_);
  }
  frustumPipeline_.createCompute(binder, "tile_frustums.comp", 4);
  // Specialization constants (light_cull.comp.glsl): 0 tile size, 1 culling on, 2 AABB test,
  // 3 depth slices, 4 list form, 5 lights put in view space by each tile (few lights).
  inlineView_ =
      settings.lightCulling && settings.lists != LightLists::Zbin && settings.lightCount <= kInlineViewMaxLights;
  cullPipeline_.createCompute(binder, "light_cull.comp", 4,
                              {{settings.tileSize, settings.lightCulling ? 1u : 0u, settings.aabb ? 1u : 0u,
                                settings.depthSlices, listModeOf(settings.lists), inlineView_ ? 1u : 0u}});
  viewPipeline_.createCompute(binder, "light_view.comp", 4, {{listModeOf(settings.lists)}});
  if (settings.lists == LightLists::Zbin) {
    sortPipeline_.createCompute(binder, "zbin_sort.comp", 4);
    binPipeline_.createCompute(binder, "zbin_bins.comp", 4);
  }
  binder.checkEveryNameRead();
}

uint64_t LightCulling::memoryBytes() const {
  uint64_t bytes = grid_.size() + indices_.size() + viewLights_.size() + viewSpheres_.size();
  if (settings_.lists == LightLists::Zbin) bytes += sortedLights_.size() + order_.size() + extents_.size();
  return bytes;
}

glm::uvec4 LightCulling::listConstants() const {
  const uint32_t words = settings_.lists == LightLists::Tile ? 0u : maskWords_;
  return {listModeOf(settings_.lists), words, settings_.lists == LightLists::Tile ? 1u : maskWords_,
          tilesX_ * tilesY_ * words};
}

glm::vec4 LightCulling::zbinConstants() const {
  if (settings_.lists != LightLists::Zbin) return glm::vec4(1.0f, 1.0f, 0.0f, 0.0f);
  return {settings_.zbinNear, float(gpu::kZBins) / std::log2(settings_.zbinFar / settings_.zbinNear), 0.0f, 0.0f};
}

LightCulling::~LightCulling() = default;

void LightCulling::dispatch(VkCommandBuffer cmd, const Pipeline& pipeline, uint32_t push, uint32_t groupsX,
                            uint32_t groupsY) const {
  VkDescriptorSet set = pipeline.set();
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.handle());
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.layout(), 0, 1, &set, 0, nullptr);
  vkCmdPushConstants(cmd, pipeline.layout(), VK_SHADER_STAGE_ALL, 0, 4, &push);
  vkCmdDispatch(cmd, groupsX, groupsY, 1);
}

void LightCulling::recordFrustums(VkCommandBuffer cmd, Sync& sync) const {
  sync.use(cmd, {{frustums_, access::kComputeWrite}});
  dispatch(cmd, frustumPipeline_, 0, (tilesX_ * tilesY_ + 63) / 64);
}

std::vector<std::string> LightCulling::subPasses() const {
  std::vector<std::string> names;
  for (const SubPassWork& w : subPassWork(settings_.lightCount)) names.push_back(w.name);
  return names;
}

std::vector<LightCulling::SubPassWork> LightCulling::subPassWork(uint32_t lightCount) const {
  const double n = std::min<uint32_t>(lightCount, gpu::kMaxLights), light = sizeof(gpu::GpuLight);
  const double viewLight = sizeof(gpu::GpuViewLight) + sizeof(glm::vec4);  // GpuViewLight + its range sphere
  std::vector<SubPassWork> w;
  if (settings_.lists == LightLists::Zbin) {
    // Every light read, then written sorted with its index and bin extent; n² key compares.
    w.push_back({"light_culling.zbin_sort", n * light + n * (light + 4 + 8), n * n});
    // The extents read, one word per bin written.
    w.push_back({"light_culling.zbin_bins", n * 8 + double(gpu::kZBins) * 4, 0});
  }
  const bool view = settings_.lightCulling && !inlineView_;
  if (view) w.push_back({"light_culling.light_view", n * light + n * viewLight, 0});
  if (w.empty()) return w;  // the tile test alone: the pass's own entry is its only one
  // The depth read once, each light's view form (or the light itself) once, the grid and lists written.
  w.push_back({"light_culling.tiles",
               4.0 * pixels_ + n * (view ? viewLight : light) + double(grid_.size() + indices_.size()), 0});
  return w;
}

void LightCulling::recordCulling(VkCommandBuffer cmd, Sync& sync, uint32_t lightCount, GpuTimer* timer) const {
  using namespace access;
  const bool subTimed = timer && !subPasses().empty();
  auto begin = [&](const char* name) {
    if (subTimed) timer->begin(cmd, std::string("light_culling.") + name);
  };
  auto end = [&] {
    if (subTimed) timer->end(cmd);
  };
  // Each dispatch declares what it reads of the ones before it and what it writes; the barriers
  // fall between the sub-passes' intervals.
  if (settings_.lists == LightLists::Zbin) {
    // Sort (ranks), then the bins and the view-space lights over the sorted lights, which read it.
    sync.use(cmd, {{sortedLights_, kComputeWrite}, {order_, kComputeWrite}, {extents_, kComputeWrite}});
    begin("zbin_sort");
    dispatch(cmd, sortPipeline_, lightCount, std::max<uint32_t>(1, (lightCount + 255) / 256));
    end();
    sync.use(cmd, {{extents_, kComputeRead}, {indices_, kComputeWrite}});
    begin("zbin_bins");
    dispatch(cmd, binPipeline_, lightCount, gpu::kZBins / 256);
    end();
  }
  if (settings_.lightCulling && !inlineView_) {  // the lights in view space, then every tile tests them
    sync.use(cmd, {{sortedLights_, kComputeRead}, {viewLights_, kComputeWrite}, {viewSpheres_, kComputeWrite}});
    begin("light_view");
    dispatch(cmd, viewPipeline_, lightCount, std::max<uint32_t>(1, (lightCount + 63) / 64));
    end();
  }
  sync.use(cmd, {{frustums_, kComputeRead},
                 {sortedLights_, kComputeRead},
                 {order_, kComputeRead},
                 {extents_, kComputeRead},
                 {viewLights_, kComputeRead},
                 {viewSpheres_, kComputeRead},
                 {grid_, kComputeWrite},
                 {indices_, kComputeWrite}});
  begin("tiles");
  dispatch(cmd, cullPipeline_, lightCount, tilesX_, tilesY_);
  end();
}

}  // namespace hb
