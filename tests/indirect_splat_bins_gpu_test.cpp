// The compute splat's binning on the real device (shaders/indirect/photon_splat_bin.comp.glsl):
// the list the gather reads is, for each coarse bin in order, the slots whose coarse box holds it,
// in slot order, at the start the bin's range gives. The CPU builds that list from the GPU's own
// coarse boxes and compares it entry for entry. Each row width renders in its own renderer, its list
// filled with ~0 first (no earlier frame's entries hide one left unwritten). A count or fill that loses,
// repeats or reorders one entry fails it; so does a bin's range or its fits flag off by one.
#include <cstdint>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "effects/indirect/indirect_part.h"
#include "effects/indirect/indirect_pass.h"
#include "frame/renderer.h"
#include "gpu_fixture.h"
#include "indirect_test_scenes.h"
#include "shared/gpu_types.h"

namespace hb {
namespace {

using namespace indirect_testing;  // indirect_test_scenes.h

class IndirectSplatBinsGpuTest : public testing::GpuTest {};

struct BinCheck {
  size_t binsHeld = 0, entries = 0, overCapacity = 0, wrongRanges = 0, wrongEntries = 0;
};

// The expected list from the GPU's coarse boxes (x0 | y0 << 8 | x1 << 16 | y1 << 24; x0 > x1 holds
// no bin), bin-major, each bin's slots ascending; a bin fits while its end is within the capacity.
BinCheck checkBins(const IndirectPass::SplatBins& b) {
  BinCheck c;
  uint64_t start = 0;
  for (uint32_t by = 0; by < b.binsY; ++by)
    for (uint32_t bx = 0; bx < b.binsX; ++bx) {
      std::vector<uint32_t> want;
      for (uint32_t s = b.first; s < b.first + b.slots; ++s) {
        const uint32_t box = b.coarse[s];
        const uint32_t x0 = box & 0xFF, y0 = (box >> 8) & 0xFF, x1 = (box >> 16) & 0xFF, y1 = box >> 24;
        if (bx >= x0 && bx <= x1 && by >= y0 && by <= y1) want.push_back(s);
      }
      const auto& got = b.bins[size_t(by) * b.binsX + bx];
      const bool fits = start + want.size() <= b.capacity;
      if (got[0] != start || got[1] != want.size() || (got[2] != 0) != fits) ++c.wrongRanges;
      c.binsHeld += !want.empty();
      c.entries += want.size();
      c.overCapacity += !fits;
      if (fits)
        for (size_t i = 0; i < want.size(); ++i)
          c.wrongEntries += start + i >= b.list.size() || b.list[start + i] != want[i];
      start += want.size();
    }
  return c;
}

// The block box at 416x128 with bins of 32 px: 13 bins across, so a binning group's row of 8, 4 or 2
// bins is followed by a partial one; more slots than a chunk (65,536), so every bin's entries come
// from several chunks, each at the start its count gave. The row width the rule picks for so few
// groups (IndirectPass::splatRowBins: 1, the single-bin count and fill), then 8, 4 and 2, forced.
TEST_F(IndirectSplatBinsGpuTest, TheListIsEachBinsSlotsInSlotOrder) {
  const Scene scene = diffuseBox("box-and-block", true);
  constexpr uint32_t W = 416, H = 128, kBin = 32;
  const RenderSettings rs =
      indirectSettings(W, H, {{"method", "raytraced"}, {"directions", 512}, {"photons", 8}, {"splat_bin", kBin}});
  std::vector<uint32_t> firstList;
  for (const uint32_t rowBins : {0u, 8u, 4u, 2u}) {  // 0: the rule's
    Renderer r(*ctx, scene, rs);
    IndirectPass& pass = *indirectPassOf(r);
    if (rowBins) pass.forceSplatRowBins(rowBins);
    pass.fillSplatList(0xFFFFFFFFu);  // no slot: an entry left unwritten differs
    r.renderFrame(true);
    const auto bins = pass.readSplatBins();
    ASSERT_TRUE(bins.has_value());
    ASSERT_EQ(bins->binsX, (W + kBin - 1) / kBin);
    ASSERT_EQ(bins->binsY, (H + kBin - 1) / kBin);
    ASSERT_NE(bins->binsX % 8, 0u) << "the test wants a partial row group";
    ASSERT_GT(bins->slots, 2 * gpu::kSplatChunk) << "the test wants several chunks";
    ASSERT_GE(bins->coarse.size(), size_t(bins->first) + bins->slots);
    const uint32_t chunks = (bins->slots + gpu::kSplatChunk - 1) / gpu::kSplatChunk;
    const uint32_t ruled = IndirectPass::splatRowBins(chunks, bins->binsX, bins->binsY);
    if (!rowBins) {
      ASSERT_EQ(ruled, 1u) << "the rule's width here should be one bin a group (the single-bin steps)";
    }
    const BinCheck c = checkBins(*bins);
    std::printf(
        "block box %ux%u, bins of %u px (%ux%u), %u slots in %u chunks, %u bins a group: %zu bins hold slots, %zu "
        "entries (capacity %u), %zu bins past it; %zu ranges and %zu entries differ from the CPU's list\n",
        W, H, kBin, bins->binsX, bins->binsY, bins->slots, chunks, rowBins ? rowBins : ruled, c.binsHeld, c.entries,
        bins->capacity, c.overCapacity, c.wrongRanges, c.wrongEntries);
    EXPECT_GT(c.binsHeld, size_t(bins->binsX * bins->binsY / 2));  // not vacuous: most bins are lit
    EXPECT_EQ(c.wrongRanges, 0u);
    EXPECT_EQ(c.wrongEntries, 0u);
    if (firstList.empty())
      firstList = bins->list;
    else
      EXPECT_EQ(bins->list, firstList) << "the list differs with " << rowBins << " bins a group";
  }
}

}  // namespace
}  // namespace hb
