#include "effects/indirect/indirect_splat.h"

#include <algorithm>
#include <cstring>

#include "base/errors.h"

namespace hb {

// The splat's constants (one run, or the later bounces' run at a stride and then the first
// bounce's), its buffers and the set-up checks; its pipelines come after the frame's target, whose
// set they use (createComputeSplatPipelines).
void IndirectPass::setUpComputeSplat(uint32_t width, uint32_t height, const VkPhysicalDeviceProperties& props) {
  const IndirectSettings& ind = settings_.indirect;
  if (!ctx_.info().computeSubgroupBallot)
    throw InputError("effects.indirect.splat=compute needs subgroup ballots in compute shaders, which device \"" +
                     ctx_.info().name + "\" lacks; use effects.indirect.splat=raster");
  auto cs = std::make_unique<ComputeSplat>(ctx_);
  gpu::SplatConstants& k = cs->constants;
  HB_ASSERT(slots() <= 0xFFFFFFFFull);
  k.slots = uint32_t(slots());
  k.chunks = uint32_t((slots() + gpu::kSplatChunk - 1) / gpu::kSplatChunk);
  k.binPixels = ind.splatBin;
  k.binsX = (width + k.binPixels - 1) / k.binPixels;
  k.binsY = (height + k.binPixels - 1) / k.binPixels;
  k.tilesX = (width + gpu::kSplatTile - 1) / gpu::kSplatTile;
  k.tilesY = (height + gpu::kSplatTile - 1) / gpu::kSplatTile;
  if (k.binsX > 255 || k.binsY > 255)
    throw InputError("effects.indirect.splat_bin=" + std::to_string(k.binPixels) + ": a " + std::to_string(width) +
                     "x" + std::to_string(height) +
                     " image has more than 255 bins a side, more than their 8-bit "
                     "coordinates hold; raise splat_bin or use splat=raster");
  // The list: room for every slot in 4 bins (the atrium's Fig. 10 photons reach about 1.3 of the
  // 128-pixel bins each). A bin whose entries would not fit is gathered from every slot instead:
  // slower, the same sum (photon_splat_bin.comp.glsl).
  const uint64_t maxEntries = props.limits.maxStorageBufferRange / 4;
  k.capacity = uint32_t(std::min<uint64_t>(std::max<uint64_t>(4 * slots(), 1u << 16), maxEntries));
  cs->all = k;
  // later_bounce_stride f > 1: two runs over the one set of bins and list, the later bounces' slots
  // at stride f, then the first bounce's.
  if (ind.laterBounceStride > 1 && ind.bounces > 1) {
    const uint32_t f = ind.laterBounceStride;
    HB_ASSERT(f * gpu::kSplatTile <= k.binPixels);  // readIndirect checked
    cs->hasLate = true;
    gpu::SplatConstants& l = cs->late;
    l = k;
    l.first = uint32_t(bounceFirstSlot(2));
    l.slots = k.slots - l.first;
    l.chunks = (l.slots + gpu::kSplatChunk - 1) / gpu::kSplatChunk;
    cs->stride = f;
    l.tilesX = ((width + f - 1) / f + gpu::kSplatTile - 1) / gpu::kSplatTile;
    l.tilesY = ((height + f - 1) / f + gpu::kSplatTile - 1) / gpu::kSplatTile;
    // Enough workgroups to fill a large GPU (2,048: 132 SMs' worth of 16 resident ones on an H200)
    // though a coarse image has few tiles; each part of a tile's list is summed apart, then in order.
    cs->parts = std::clamp((2048u + l.tilesX * l.tilesY - 1) / (l.tilesX * l.tilesY), 1u, 16u);
    k.slots = l.first;
    k.chunks = (k.slots + gpu::kSplatChunk - 1) / gpu::kSplatChunk;
  }
  k.workBase = cs->hasLate ? cs->late.tilesX * cs->late.tilesY * cs->parts : 0;
  for (gpu::SplatConstants* run : {&k, &cs->late, &cs->all})
    run->rowBins = splatRowBins(run->chunks, run->binsX, run->binsY);
  const VkBufferUsageFlags use = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  cs->boxes = Buffer(ctx_, std::max<uint64_t>(8, slots() * 8), use, false, MemClass::Other);
  const VkBufferUsageFlags readable = use | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;  // readSplatBins
  cs->coarse = Buffer(ctx_, std::max<uint64_t>(4, slots() * 4), readable, false, MemClass::Other);
  cs->counts =
      Buffer(ctx_, uint64_t(k.binsX) * k.binsY * std::max(k.chunks, cs->late.chunks) * 4, use, false, MemClass::Other);
  cs->bins = Buffer(ctx_, uint64_t(k.binsX) * k.binsY * 16, readable, false, MemClass::Other);
  cs->list = Buffer(ctx_, uint64_t(k.capacity) * 4, readable | VK_BUFFER_USAGE_TRANSFER_DST_BIT, false,
                    MemClass::Other);  // filled by tests (fillSplatList)
  cs->work = Buffer(ctx_, (uint64_t(k.workBase) + uint64_t(k.tilesX) * k.tilesY) * 8,
                    use | VK_BUFFER_USAGE_TRANSFER_SRC_BIT, false, MemClass::Other);
  computeSplat_ = std::move(cs);
}

void IndirectPass::createComputeSplatPipelines() {
  ComputeSplat* cs = computeSplat_.get();
  if (!cs) return;
  for (uint32_t mode = 0; mode < 6; ++mode) {
    auto p = std::make_unique<Pipeline>(ctx_);
    p->createLayout({frame_.sets->layout()}, sizeof(gpu::SplatConstants));
    p->createCompute(*shaders_, "photon_splat_bin.comp", SpecConstants{{mode}});
    cs->bin.push_back(std::move(p));
  }
  for (uint32_t run = 0; run < (cs->hasLate ? 2u : 1u); ++run)
    for (uint32_t count : {0u, 1u}) {
      // STRIDE, LATE: the first bounce's run adds the later bounces' (1, f); theirs (f, 1).
      const uint32_t stride = run ? cs->stride : 1u, late = run || !cs->hasLate ? 1u : cs->stride;
      auto g = std::make_unique<Pipeline>(ctx_);
      g->createLayout({frame_.sets->layout()}, sizeof(gpu::SplatConstants));
      g->createCompute(
          *shaders_, count ? "photon_splat_count.comp" : "photon_splat.comp",
          SpecConstants{{uint32_t(settings_.normals), uint32_t(settings_.worldPos), count, stride, late, cs->parts}});
      cs->gather[run][count] = std::move(g);
    }
}

// Boxes, counts, starts, lists, then the gather (photon_splat_bin.comp.glsl, photon_splat.comp.glsl),
// each step reading what the one before wrote.
// With later_bounce_stride f > 1, the later bounces' count, scan, fill and gather come first, named
// "photon_splat.later.*".
std::vector<std::string> IndirectPass::splatSubPasses() const {
  if (!computeSplat_) return {};
  std::vector<std::string> names = {"photon_splat.boxes"};
  if (computeSplat_->hasLate)
    names.insert(names.end(), {"photon_splat.later.count", "photon_splat.later.scan", "photon_splat.later.fill",
                               "photon_splat.later.gather"});
  names.insert(names.end(), {"photon_splat.count", "photon_splat.scan", "photon_splat.fill", "photon_splat.gather"});
  return names;
}

void IndirectPass::recordComputeSplat(VkCommandBuffer cmd, Sync& sync, const Target& t, GpuTimer* timer,
                                      bool analysis) const {
  using namespace access;
  const ComputeSplat& cs = *computeSplat_;
  // Each step reads the photons and what the steps before it wrote, and updates the bins; a gather
  // writes the target (the later bounces' gather its `late` image, which the last one reads).
  std::vector<Use> step = {{t.photons, kComputeRead},  {cs.boxes, kComputeWrite}, {cs.coarse, kComputeWrite},
                           {cs.counts, kComputeWrite}, {cs.bins, kComputeWrite},  {cs.list, kComputeWrite}};
  const VkDescriptorSet set = t.sets->set();
  const std::vector<std::string> names = splatSubPasses();
  size_t next = 0;
  auto dispatch = [&](const Pipeline& p, const gpu::SplatConstants& k, uint32_t x, uint32_t y,
                      std::vector<Use> extra = {}, uint32_t z = 1) {
    std::vector<Use> uses = step;
    uses.insert(uses.end(), extra.begin(), extra.end());
    sync.use(cmd, uses);
    if (timer) timer->begin(cmd, names[next]);
    ++next;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.handle());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.layout(), 0, 1, &set, 0, nullptr);
    vkCmdPushConstants(cmd, p.layout(), VK_SHADER_STAGE_ALL, 0, sizeof k, &k);
    vkCmdDispatch(cmd, x, y, z);
    if (timer) timer->end(cmd);
  };
  const uint32_t slotGroups = (cs.all.slots + 255) / 256, gx = std::max(1u, std::min(slotGroups, 65535u));
  dispatch(*cs.bin[0], cs.all, gx, (slotGroups + gx - 1) / gx);
  if (analysis) step.push_back({cs.work, kComputeWrite});
  auto run = [&](uint32_t r, const gpu::SplatConstants& k, std::vector<Use> gatherUses) {
    const uint32_t rows = (k.binsX + k.rowBins - 1) / k.rowBins * k.binsY;  // rowBins bins a group
    const bool single = k.rowBins == 1;                                     // MODE 4, 5: a single bin's loops
    dispatch(*cs.bin[single ? 4 : 1], k, k.chunks, rows);
    dispatch(*cs.bin[2], k, 1, 1);
    dispatch(*cs.bin[single ? 5 : 3], k, k.chunks, rows);
    dispatch(*cs.gather[r][analysis ? 1 : 0], k, k.tilesX, k.tilesY, std::move(gatherUses), r ? cs.parts : 1u);
  };
  if (cs.hasLate) run(1, cs.late, {{t.late, kComputeWrite}});
  std::vector<Use> last = {{t.irradiance, kComputeWrite}};
  if (cs.hasLate) last.push_back({t.late, kComputeRead});
  run(0, cs.constants, std::move(last));
  HB_ASSERT(next == names.size());
  if (analysis) splatCounted_ = true;
}

// A count or fill group reads each slot's coarse box once for rowBins bins of a row. The widest row
// that leaves 512 groups (about 4 of 256 threads for each of an H200's 132 SMs); a run of few chunks
// (the first bounce's at a stride) needs the groups more than the shared reads, since a group's 256
// rounds are then the step's time (measured on the H200: results/h200/raster3d-52/splat-rows).
uint32_t IndirectPass::splatRowBins(uint64_t chunks, uint32_t binsX, uint32_t binsY) {
  for (uint32_t r = gpu::kSplatBinRow; r > 1; r /= 2)
    if (chunks * ((binsX + r - 1) / r) * binsY >= 512) return r;
  return 1;
}

void IndirectPass::forceSplatRowBins(uint32_t rowBins) {
  HB_ASSERT(computeSplat_ && rowBins >= 1 && rowBins <= gpu::kSplatBinRow && (rowBins & (rowBins - 1)) == 0);
  for (gpu::SplatConstants* run : {&computeSplat_->constants, &computeSplat_->late, &computeSplat_->all})
    run->rowBins = rowBins;
}

void IndirectPass::fillSplatList(uint32_t value) {
  HB_ASSERT(computeSplat_);
  ctx_.submitAndWait(
      [&](VkCommandBuffer cmd) { vkCmdFillBuffer(cmd, computeSplat_->list.handle(), 0, VK_WHOLE_SIZE, value); },
      "the splat list filled for a test");
}

nlohmann::json IndirectPass::splatPipelineStatistics() const {
  if (!computeSplat_ || !ctx_.info().pipelineStatistics) return nullptr;
  const ComputeSplat& cs = *computeSplat_;
  nlohmann::json j = {{"count", pipelineStatistics(ctx_, cs.bin[1]->handle())},
                      {"fill", pipelineStatistics(ctx_, cs.bin[3]->handle())},
                      {"gather", pipelineStatistics(ctx_, cs.gather[0][0]->handle())}};
  if (cs.hasLate) j["later.gather"] = pipelineStatistics(ctx_, cs.gather[1][0]->handle());
  return j;
}

std::optional<IndirectPass::SplatBins> IndirectPass::readSplatBins() const {
  if (!computeSplat_) return std::nullopt;
  const gpu::SplatConstants& k = computeSplat_->constants;  // the last run: the first bounce's, or all
  SplatBins out;
  out.binsX = k.binsX;
  out.binsY = k.binsY;
  out.first = k.first;
  out.slots = k.slots;
  out.capacity = k.capacity;
  auto words = [this](const Buffer& b) {
    const std::vector<uint8_t> bytes = readbackBuffer(ctx_, b);
    std::vector<uint32_t> w(bytes.size() / 4);
    std::memcpy(w.data(), bytes.data(), w.size() * 4);
    return w;
  };
  out.coarse = words(computeSplat_->coarse);
  const std::vector<uint32_t> bins = words(computeSplat_->bins);
  uint64_t entries = 0;
  for (size_t b = 0; b + 3 < bins.size(); b += 4) {
    out.bins.push_back({bins[b], bins[b + 1], bins[b + 2]});
    entries = std::max<uint64_t>(entries, uint64_t(bins[b]) + bins[b + 1]);
  }
  out.list = words(computeSplat_->list);
  out.list.resize(std::min<uint64_t>(entries, out.list.size()));
  return out;
}

std::optional<IndirectPass::SplatStats> IndirectPass::splatStats() const {
  if (!computeSplat_) return std::nullopt;
  const std::vector<uint8_t> bytes = readbackBuffer(ctx_, computeSplat_->bins);
  SplatStats st;
  st.bins = bytes.size() / 16;
  st.capacity = computeSplat_->constants.capacity;
  for (size_t b = 0; b < st.bins; ++b) {
    uint32_t v[4];
    std::memcpy(v, bytes.data() + 16 * b, sizeof v);
    st.entries += v[1];
    st.overCapacity += v[2] == 0;
  }
  st.counted = splatCounted_;
  if (st.counted) {
    const std::vector<uint8_t> work = readbackBuffer(ctx_, computeSplat_->work);
    const uint32_t firstTile = computeSplat_->constants.workBase;
    for (size_t i = 0; i < work.size() / 8; ++i) {
      uint32_t v[2];
      std::memcpy(v, work.data() + 8 * i, sizeof v);
      (i < firstTile ? st.laterTests : st.tests) += v[0];
      (i < firstTile ? st.laterTerms : st.terms) += v[1];
    }
  }
  return st;
}

}  // namespace hb
